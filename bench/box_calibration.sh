#!/usr/bin/env bash
# Re-measures the box calibration constants of lib/detect/box_calibration.c: our cascade boxes
# (frontal alt2, profile, profile on the mirrored photo, each run on every photo of
# ../shared/photos with the detect.* defaults) against the boxes of dlib's HOG detector (which
# dlib's landmark model was trained on), fitted per cascade by least squares.
#   bench/box_calibration.sh      (a few minutes the first time: dlib's detector on every photo)
source "$(dirname "$0")/dlib_ref_common.sh"
bench_cc "$tools/detect_vs_dlib" bench/detect_vs_dlib.c
dlib_hog
"$tools/detect_vs_dlib" calibrate "$tools/dlib_hog.jsonl" "${photos[@]}"
