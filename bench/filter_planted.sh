#!/usr/bin/env bash
# Planted-failure benchmark of the filter stage (section 4.2, Algorithm 1): precision and recall of
# the dropped set for shape only, texture only and both, over every photo set in ../shared/photos,
# planted rates 0/10/20/30 %, several seeds; then the runtime for 100 photos and a contact sheet.
# Good detections come from dlib's own landmark model (build/tools/dlib_ref, built with the tests
# when libdlib-dev is installed); they are cached in build/tools/lm_<set>.jsonl after the first run.
#   bench/filter_planted.sh [--seeds N] [--sets A,B] [--photos N] [name=value ...]   e.g. filter.omega=3
# --photos N: small albums, four windows of N consecutive photos of each set instead of the whole set.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${FRIG_BUILD:-build}
cmake --build "$build" -j2 --target test_filter_planted dlib_ref >/dev/null
mkdir -p "$build/bench"
exec "$build/tests/test_filter_planted" --full --sheet "$build/bench" "$@"
