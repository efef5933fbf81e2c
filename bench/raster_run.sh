#!/usr/bin/env bash
# Build and run the rasterizer's benchmark and visual demo against the static library of an
# existing build (default build/; configure and build it first: cmake -S . -B build && cmake
# --build build -j2). Usage: bench/raster_run.sh [build-dir] [png-output-dir]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
out=${2:-$build/raster-demo}
mkdir -p "$out"
libs="$(pkg-config --libs openblas lapacke libpng libjpeg libcjson) -lcholmod -lsuitesparseconfig -fopenmp -lm"
for prog in raster_bench raster_demo; do
  cc -std=c11 -O3 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -Wall -Wextra -Werror -Iinclude -Ilib \
    -I/usr/include/suitesparse "bench/$prog.c" "$build/libfrig.a" $libs -o "$build/$prog"
done
"$build/raster_bench"
"$build/raster_demo" "$out"
