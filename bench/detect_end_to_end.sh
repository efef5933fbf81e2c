#!/usr/bin/env bash
# The detect stage end to end on every photo of ../shared/photos, single thread, in one run:
# our detector (frontal alt2; profile + mirrored profile where it finds nothing) + calibrated
# boxes + our predictor against dlib's full pipeline (HOG detector upsampled once + its
# predictor) and the iBUG ground truth; detection rate per photo set; speed ratios (our
# detector vs OpenCV's detectMultiScale per megapixel, our predictor vs dlib's per face).
#   bench/detect_end_to_end.sh    (about 8 minutes; dlib's HOG results are cached in build/tools)
# Needs libdlib-dev, python3-opencv, opencv-data (scripts/install-deps.sh --test); exits 77 without.
source "$(dirname "$0")/dlib_ref_common.sh"
if ! /usr/bin/python3 -c 'import cv2' 2>/dev/null; then
  echo "SKIPPED: needs python3-opencv (scripts/install-deps.sh --test)" >&2
  exit 77
fi
bench_cc "$tools/detect_vs_dlib" bench/detect_vs_dlib.c
dlib_hog
# dlib's predictor alone, on its own boxes, reading the image before each face (its tool's pattern).
/usr/bin/python3 -c '
import json, sys
for line in open(sys.argv[1]):
    j = json.loads(line)
    print(j["image"], *j["box"])' "$tools/dlib_hog.jsonl" > "$tools/dlib_boxes.txt"
"$tools/dlib_ref" "$model" --boxes "$tools/dlib_boxes.txt" > "$tools/dlib_boxes.jsonl" 2> "$tools/dlib_boxes.err"
dlib_us=$(sed -n 's/.*(\([0-9.]*\) us\/face).*/\1/p' "$tools/dlib_boxes.err" | tail -n 1)
echo "dlib's predictor: $(tail -n 1 "$tools/dlib_boxes.err")"
# OpenCV's detectMultiScale with the stage's frontal cascade and parameters.
/usr/bin/python3 "$shared/tools/opencv_ref.py" "${photos[@]}" > "$tools/opencv_alt2.jsonl" 2> "$tools/opencv_alt2.err"
cv_s=$(sed -n 's/total detector seconds \([0-9.]*\) .*/\1/p' "$tools/opencv_alt2.err")
echo "OpenCV: $(tail -n 1 "$tools/opencv_alt2.err")"
echo
"$tools/detect_vs_dlib" e2e "$tools/dlib_hog.jsonl" --opencv-seconds "$cv_s" --dlib-us "$dlib_us" --gray-check \
  "${photos[@]}"
