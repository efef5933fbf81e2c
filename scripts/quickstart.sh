#!/usr/bin/env bash
# Install the dependencies, build libfrig and the frig command, and run the main job on the
# embedded default: import the ICT-FaceKit model once, then take the sample photo set
# (100 LFW photos of one person) through the stages that exist so far - detect, filter,
# fit - and export the subject's rig to ./out (out/rig.glb, out/shapes/*.obj). The
# workspace (report.json, overlays of every photo) is ./out/workspace.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build build -j "$(nproc)"
build/frig --version
shared="${FRIG_SHARED:-../shared}"
photos="${1:-$shared/photos/lfw_tony_blair}"
build/frig model import-ict "$shared/ict-facekit"
build/frig detect "$photos" -w out/workspace
build/frig filter -w out/workspace
build/frig fit -w out/workspace
build/frig export -w out/workspace -o out
