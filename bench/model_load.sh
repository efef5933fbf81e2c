#!/usr/bin/env bash
# Times the ICT import, model save/load, eval and glTF export (medians) against the built
# library: bench/model_load.sh [ICT_DIR]. Build first: cmake --build build.
set -euo pipefail
cd "$(dirname "$0")/.."
ict="${1:-${FRIG_SHARED:-../shared}/ict-facekit}"
out="build/bench"; mkdir -p "$out"
cc -std=c11 -O2 -D_POSIX_C_SOURCE=200809L -Iinclude bench/model_load.c -o "$out/model_load" \
  -Lbuild -lfrig -Wl,-rpath,"$PWD/build"
"$out/model_load" "$ict" "$out/bench.frigmodel"
