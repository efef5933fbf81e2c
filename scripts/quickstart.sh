#!/usr/bin/env bash
# Install the dependencies, build libfrig and the frig command, and run the main job on
# the embedded default. Until the whole pipeline lands, the main job describes the sample
# photos as libfrig reads them.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build build -j "$(nproc)"
build/frig --version
shared="${FRIG_SHARED:-../shared}"
build/frig info "$shared"/photos/landmarks_300w_lfpw/*.png
