#!/usr/bin/env bash
# Install the dependencies, build libfrig and the frig command, and run the main job on
# the embedded default: import the ICT-FaceKit model once, then export its template rig
# (mean face + ARKit-named expressions) to ./out as glTF (out/rig.glb) and OBJ (out/shapes/).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build build -j "$(nproc)"
build/frig --version
shared="${FRIG_SHARED:-../shared}"
build/frig model import-ict "$shared/ict-facekit" && build/frig model export -o out
