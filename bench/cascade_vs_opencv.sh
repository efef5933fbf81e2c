#!/usr/bin/env bash
# Our cascade evaluator against OpenCV 4.6's detectMultiScale (Debian python3-opencv via
# ../shared/tools/opencv_ref.py), single thread each, on the same photos with the same
# parameters: detector seconds per megapixel and their ratio, then box agreement (share of
# OpenCV's boxes we have with IoU >= 0.9, share of ours OpenCV has, identical box lists).
# Use: bench/cascade_vs_opencv.sh [--cascade XML] [--scale 1.1] [--neighbors 3] [--min-size 30] [PHOTO...]
# Without photos: every JPEG and PNG under ../shared/photos. Needs a build in build/.
set -euo pipefail
cd "$(dirname "$0")/.."
opts=()
while [ $# -gt 0 ] && [ "${1#--}" != "$1" ]; do opts+=("$1" "$2"); shift 2; done
if [ $# -eq 0 ]; then
  mapfile -t photos < <(ls ../shared/photos/*/*.jpg ../shared/photos/*/*.png | sort)
else
  photos=("$@")
fi
[ -f build/libfrig.a ] || { cmake -S . -B build >/dev/null && cmake --build build -j2 >/dev/null; }
tool=build/bench-cascade-detect
cc -O3 -std=c11 -D_POSIX_C_SOURCE=200809L -Iinclude -Ilib bench/cascade_detect.c -o "$tool" build/libfrig.a \
  $(pkg-config --libs libpng libjpeg libcjson lapacke openblas) -lcholmod -lsuitesparseconfig -fopenmp -lm
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "${#photos[@]} photos, options: ${opts[*]:-defaults (alt2, 1.1, 3, 30)}"
OMP_NUM_THREADS=1 "$tool" "${opts[@]}" "${photos[@]}" > "$out/ours.jsonl" 2> "$out/ours.err"
/usr/bin/python3 ../shared/tools/opencv_ref.py "${opts[@]}" "${photos[@]}" > "$out/ref.jsonl" 2> "$out/ref.err"
/usr/bin/python3 - "$out" <<'PY'
import json, sys
d = sys.argv[1]
ours = {j["image"]: j for j in map(json.loads, open(d + "/ours.jsonl"))}
ref = {j["image"]: j for j in map(json.loads, open(d + "/ref.jsonl"))}
def iou(a, b):
    x0, y0 = max(a[0], b[0]), max(a[1], b[1])
    x1, y1 = min(a[0] + a[2], b[0] + b[2]), min(a[1] + a[3], b[1] + b[3])
    i = max(0, x1 - x0) * max(0, y1 - y0)
    return i / (a[2] * a[3] + b[2] * b[3] - i)
mp = so = sr = 0.0
nr = no = hr = ho = same = n = 0
for img, o in ours.items():
    r = ref.get(img)
    if r is None or "boxes" not in o or "boxes" not in r:
        continue
    n += 1
    mp += o["width"] * o["height"] / 1e6
    so += o["seconds"]; sr += r["seconds"]
    a, b = r["boxes"], o["boxes"]
    nr += len(a); no += len(b)
    hr += sum(any(iou(x, y) >= 0.9 for y in b) for x in a)
    ho += sum(any(iou(x, y) >= 0.9 for x in a) for y in b)
    same += a == b
print(f"speed: ours {so / mp:.3f} s/MP, OpenCV {sr / mp:.3f} s/MP over {mp:.1f} MP; ratio ours/OpenCV {so / sr:.2f}")
print(f"agreement on {n} photos: OpenCV's {nr} boxes, {hr} in ours ({100.0 * hr / max(nr, 1):.2f}%); "
      f"our {no} boxes, {ho} in OpenCV's ({100.0 * ho / max(no, 1):.2f}%); identical lists on {same} photos")
PY
