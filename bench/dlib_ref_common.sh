# Sourced by the bench scripts that compare with dlib (predictor_vs_dlib.sh, box_calibration.sh,
# detect_end_to_end.sh): paths, the build of libfrig and of ../shared/tools/dlib_ref.cpp, the
# photo list, and dlib's HOG detector + predictor over every photo (cached in build/tools/
# dlib_hog.jsonl; FRIG_BENCH_FRESH=1 reruns it). Exits 77 when dlib is not installed.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
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

# bench_cc OUT SOURCE: a bench program linked with the static library.
bench_cc() {
  cc -O3 -std=c11 -D_POSIX_C_SOURCE=200809L -Wall -Wextra -Werror "$2" -Iinclude -Ilib -Itests \
    "$build/libfrig.a" $(pkg-config --libs libcjson openblas lapacke libpng libjpeg) -lcholmod -lsuitesparseconfig \
    -fopenmp -lm -o "$1"
}

mapfile -t photos < <(find "$shared/photos" -type f \( -iname '*.jpg' -o -iname '*.jpeg' -o -iname '*.png' \) | sort)

# dlib's HOG detector (upsampled once) + landmarks on every photo, into $tools/dlib_hog.jsonl.
dlib_hog() {
  local list=$tools/dlib_hog.photos
  if [ "${FRIG_BENCH_FRESH:-0}" = 1 ] || [ ! -s "$tools/dlib_hog.jsonl" ] || [ ! -f "$list" ] ||
     [ "$tools/dlib_ref" -nt "$tools/dlib_hog.jsonl" ] || ! cmp -s "$list" <(printf '%s\n' "${photos[@]}"); then
    echo "photos: ${#photos[@]}; dlib's HOG detector (upsampled once) + landmarks..."
    "$tools/dlib_ref" "$model" "${photos[@]}" > "$tools/dlib_hog.jsonl" 2> "$tools/dlib_hog.err"
    printf '%s\n' "${photos[@]}" > "$list"
  else
    echo "photos: ${#photos[@]}; dlib's HOG results from $tools/dlib_hog.jsonl (FRIG_BENCH_FRESH=1 reruns)"
  fi
  tail -n 1 "$tools/dlib_hog.err"
}
