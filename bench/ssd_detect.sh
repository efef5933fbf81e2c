#!/usr/bin/env bash
# face-api's SSD detector on every photo of ../shared/photos against the cascade path and dlib's
# HOG detector (cached): the SSD row of lib/detect/box_calibration.c, photos with a face per
# set, NME of face-api's landmark net and of dlib's predictor on the mapped SSD box where ground
# truth exists, and times (one thread).
#   bench/ssd_detect.sh      (needs scripts/install-deps.sh --test and face-api's networks)
source "$(dirname "$0")/dlib_ref_common.sh"
cmake --build "$build" -j2 --target bench_detect_vs_dlib >/dev/null
dlib_hog
"$build/bench/detect_vs_dlib" ssd "$tools/dlib_hog.jsonl" "${photos[@]}"
