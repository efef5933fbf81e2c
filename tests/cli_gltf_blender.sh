#!/usr/bin/env bash
# Blender (headless) imports the exported rig.glb, sees every shape key by its ARKit name,
# and the mesh with jawOpen at 1.0 matches ICT's jawOpen.obj within 1e-5 m everywhere.
set -u
. "$FRIG_SOURCE_DIR/tests/scripts/model_fixture.sh"
command -v blender >/dev/null || frig_test_skip "blender is not installed (scripts/install-deps.sh --test)"
frig_test_model || frig_test_skip "no ICT-FaceKit data"
tmp="$FRIG_BINARY_DIR/test-tmp/cli_gltf_blender"; rm -rf "$tmp"; mkdir -p "$tmp"
. "$FRIG_SOURCE_DIR/tests/scripts/scratch.sh"
# With a face texture, so the importer also meets the embedded images and the blended materials.
python3 "$FRIG_SOURCE_DIR/tests/scripts/make_png.py" "$tmp/albedo.png" 128 128 || exit 1
"$FRIG_CLI" --quiet model export --model "$FRIG_TEST_MODEL" --texture "$tmp/albedo.png" -o "$tmp/out" >/dev/null || exit 1
# Blender's own Python (with Debian's numpy); its home stays in the build tree.
HOME="$tmp" blender -b --factory-startup --python-exit-code 1 \
  --python "$FRIG_SOURCE_DIR/tests/scripts/blender_check.py" -- "$tmp/out/rig.glb" "$FRIG_TEST_ICT" > "$tmp/log" 2>&1
rc=$?
grep -E "shape keys|vertices|jawOpen|CHECK|Error|error" "$tmp/log"
[ $rc = 0 ] && grep -q "BLENDER CHECK OK" "$tmp/log"
