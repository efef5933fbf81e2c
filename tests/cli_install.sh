#!/usr/bin/env bash
# Install to a temporary prefix and build the examples against the installed library, both
# through pkg-config and through CMake's find_package; run them. Also: only frig_ symbols
# are exported, and the SONAME is libfrig.so.0.
set -eu
tmp="$FRIG_BINARY_DIR/test-tmp/cli_install"; rm -rf "$tmp"; mkdir -p "$tmp"
. "$FRIG_SOURCE_DIR/tests/scripts/scratch.sh"
prefix="$tmp/prefix"
cmake --install "$FRIG_BINARY_DIR" --prefix "$prefix" >/dev/null
lib="$prefix/lib/libfrig.so"
[ -e "$prefix/lib/x86_64-linux-gnu/libfrig.so" ] && lib="$prefix/lib/x86_64-linux-gnu/libfrig.so"
libdir=$(dirname "$lib")

bad=$(nm -D --defined-only "$lib" | awk '{print $3}' | grep -v '^frig_' || true)
if [ -n "$bad" ]; then echo "exported names without the frig_ prefix:"; echo "$bad"; exit 1; fi
echo "exported: $(nm -D --defined-only "$lib" | wc -l) symbols, all frig_*"
soname=$(objdump -p "$lib" | awk '/SONAME/{print $2}')
[ "$soname" = "libfrig.so.0" ] || { echo "SONAME is '$soname'"; exit 1; }

extra="${FRIG_EXAMPLE_CFLAGS:-}"
export PKG_CONFIG_PATH="$libdir/pkgconfig"
cc -std=c11 -Wall -Wextra -Werror $extra -o "$tmp/load_image" "$FRIG_SOURCE_DIR/examples/load_image.c" \
  $(pkg-config --cflags --libs frig)
# Make a small PNG with the installed command, then read it back with the example.
"$prefix/bin/frig" --version
LD_LIBRARY_PATH="$libdir" "$tmp/load_image" "$tmp/made.png" > "$tmp/out"
grep -q "made.png: 64x32, 3 channels" "$tmp/out" || { cat "$tmp/out"; exit 1; }
# The detect example (frig/detect.h installed, its symbols exported); run when the data is there.
cc -std=c11 -Wall -Wextra -Werror $extra -o "$tmp/detect_faces" "$FRIG_SOURCE_DIR/examples/detect_faces.c" \
  $(pkg-config --cflags --libs frig)
photo="${FRIG_SHARED:-$FRIG_SOURCE_DIR/../shared}/photos/lfw_tony_blair/Tony_Blair_0001.jpg"
if [ -f "$photo" ] && [ -f /usr/share/dlib/shape_predictor_68_face_landmarks.dat ] &&
   [ -f /usr/share/opencv4/haarcascades/haarcascade_frontalface_alt2.xml ]; then
  LD_LIBRARY_PATH="$libdir" "$tmp/detect_faces" "$photo" > "$tmp/faces"
  # face-api's SSD detector (where its weights are installed) also finds the face cut by the
  # crop's left edge, as the package itself does; the cascades find one face.
  models="${FRIG_FACE_MODELS:-/usr/local/share/frig/face-api/model}"
  if [ -f "$models/ssd_mobilenetv1_model-weights_manifest.json" ]; then
    grep -q "Tony_Blair_0001.jpg: 2 faces$" "$tmp/faces" && grep -q ", ssd, score 0.99" "$tmp/faces" ||
      { cat "$tmp/faces"; exit 1; }
  else
    grep -q "Tony_Blair_0001.jpg: 1 face$" "$tmp/faces" || { cat "$tmp/faces"; exit 1; }
  fi
fi

# The pipeline one stage at a time through the public API (examples/stage_by_stage.c): built
# against the installed library (sfs and retarget included); run on five shared photos (LFW's 0001-0006, 0004 not among them) when the model and data are there.
cc -std=c11 -Wall -Wextra -Werror $extra -o "$tmp/stage_by_stage" "$FRIG_SOURCE_DIR/examples/stage_by_stage.c" \
  $(pkg-config --cflags --libs frig)
. "$FRIG_SOURCE_DIR/tests/scripts/model_fixture.sh"
if [ -f "$photo" ] && [ -f /usr/share/dlib/shape_predictor_68_face_landmarks.dat ] && frig_test_model; then
  sets=$(dirname "$photo")
  LD_LIBRARY_PATH="$libdir" "$tmp/stage_by_stage" "$FRIG_TEST_MODEL" "$tmp/sbs" "$sets"/Tony_Blair_000[1-6].jpg > "$tmp/sbs.out"
  cat "$tmp/sbs.out"
  grep -q "^detect: 5 photos, 5 with a usable face$" "$tmp/sbs.out" && grep -q "^export: .*rig.glb and .*shapes/ (55 blendshapes)$" "$tmp/sbs.out" &&
    grep -q "^sfs: [1-5] point clouds" "$tmp/sbs.out" && grep -q "^retarget: [1-3] rounds, [1-5] photos" "$tmp/sbs.out" &&
    [ -s "$tmp/sbs/albedo.png" ] && grep -aq '"image/png"' "$tmp/sbs/rig.glb" &&
    [ -s "$tmp/sbs/rig.glb" ] || { echo "stage_by_stage did not run through"; exit 1; }
fi

cmake -S "$FRIG_SOURCE_DIR/examples" -B "$tmp/cmake-build" -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_C_FLAGS="$extra" >/dev/null
cmake --build "$tmp/cmake-build" >/dev/null
LD_LIBRARY_PATH="$libdir" "$tmp/cmake-build/load_image" "$tmp/made2.png" | grep -q "64x32"
echo "installed library: pkg-config and CMake builds of the example work"
