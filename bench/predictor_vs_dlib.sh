#!/usr/bin/env bash
# Our landmark predictor (lib/detect/shape_predictor*) against dlib's, single thread, on every
# face dlib's HOG detector finds in ../shared/photos: time per face as a ratio, and the distance
# of our points to dlib's on identical boxes (mean and max, pixels), overall and per set.
#   bench/predictor_vs_dlib.sh            (builds build/ and build/tools/, takes a few minutes)
# Needs libdlib-dev (scripts/install-deps.sh --test); exits 77 without it.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
shared=${FRIG_SHARED:-$root/../shared}
build=${FRIG_BUILD_DIR:-$root/build}
model=/usr/share/dlib/shape_predictor_68_face_landmarks.dat
tools=$build/tools
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1

if ! pkg-config --exists dlib-1 || ! command -v g++ >/dev/null || [ ! -f "$model" ]; then
  echo "SKIPPED: needs libdlib-dev, g++ and $model (scripts/install-deps.sh --test)" >&2
  exit 77
fi
cmake -S . -B "$build" -DFRIG_WERROR=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$build" -j2 --target frig_static >/dev/null
mkdir -p "$tools"
if [ ! "$tools/dlib_ref" -nt "$shared/tools/dlib_ref.cpp" ]; then
  echo "building dlib_ref (dlib $(pkg-config --modversion dlib-1))"
  g++ -O2 -DDLIB_JPEG_SUPPORT -DDLIB_PNG_SUPPORT "$shared/tools/dlib_ref.cpp" -o "$tools/dlib_ref" \
    $(pkg-config --cflags --libs dlib-1)
fi
cc -O3 -std=c11 -D_POSIX_C_SOURCE=200809L -Wall -Wextra -Werror bench/predictor_vs_dlib.c -Iinclude -Ilib -Itests \
  "$build/libfrig.a" $(pkg-config --libs libcjson openblas lapacke libpng libjpeg) -lcholmod -lsuitesparseconfig \
  -fopenmp -lm -o "$tools/predictor_vs_dlib"

mapfile -t photos < <(find "$shared/photos" -type f \( -iname '*.jpg' -o -iname '*.jpeg' -o -iname '*.png' \) | sort)
echo "photos: ${#photos[@]}; dlib's HOG detector (upsampled once) + landmarks..."
"$tools/dlib_ref" "$model" "${photos[@]}" > "$tools/dlib_hog.jsonl" 2> "$tools/dlib_hog.err"
tail -n 1 "$tools/dlib_hog.err"
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
