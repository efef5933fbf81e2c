#!/usr/bin/env bash
# Our landmark predictor (lib/detect/shape_predictor*) against dlib's, single thread, on every
# face dlib's HOG detector finds in ../shared/photos: time per face as a ratio, and the distance
# of our points to dlib's on identical boxes (mean and max, pixels), overall and per set.
#   bench/predictor_vs_dlib.sh            (builds build/ and build/tools/, takes a few minutes)
# Needs libdlib-dev (scripts/install-deps.sh --test); exits 77 without it.
source "$(dirname "$0")/dlib_ref_common.sh"
bench_cc "$tools/predictor_vs_dlib" bench/predictor_vs_dlib.c
FRIG_BENCH_FRESH=1 dlib_hog
# dlib again on its own boxes, reading the image before each face: the timing pattern we mirror.
/usr/bin/python3 -c '
import json, sys
for line in open(sys.argv[1]):
    j = json.loads(line)
    print(j["image"], *j["box"])' "$tools/dlib_hog.jsonl" > "$tools/dlib_boxes.txt"
"$tools/dlib_ref" "$model" --boxes "$tools/dlib_boxes.txt" > "$tools/dlib_boxes.jsonl" 2> "$tools/dlib_boxes.err"
tail -n 1 "$tools/dlib_boxes.err"
if ! cmp -s <(sed 's/"score":[^,]*,//' "$tools/dlib_hog.jsonl") <(sed 's/"score":[^,]*,//' "$tools/dlib_boxes.jsonl"); then
  echo "note: dlib's points differ between its two runs" >&2
fi
dlib_us=$(sed -n 's/.*(\([0-9.]*\) us\/face).*/\1/p' "$tools/dlib_boxes.err" | tail -n 1)
"$tools/predictor_vs_dlib" "$model" "$tools/dlib_boxes.jsonl" "$dlib_us"
