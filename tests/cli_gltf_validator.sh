#!/usr/bin/env bash
# The exported rig.glb passes the Khronos glTF validator with 0 errors and 0 warnings: the plain
# export, one with a face texture embedded and one with the eye overlays left out.
# Needs node and gltf-validator in $FRIG_TOOLS_DIR (scripts/install-deps.sh --test).
set -u
. "$FRIG_SOURCE_DIR/tests/scripts/model_fixture.sh"
tools="${FRIG_TOOLS_DIR:-$FRIG_SOURCE_DIR/build/tools}"
command -v node >/dev/null || frig_test_skip "node is not installed (scripts/install-deps.sh --test)"
[ -f "$tools/node_modules/gltf-validator/package.json" ] ||
  frig_test_skip "gltf-validator is not in $tools (scripts/install-deps.sh --test)"
frig_test_model || frig_test_skip "no ICT-FaceKit data"
tmp="$FRIG_BINARY_DIR/test-tmp/cli_gltf_validator"; rm -rf "$tmp"; mkdir -p "$tmp"
. "$FRIG_SOURCE_DIR/tests/scripts/scratch.sh"
echo '{"identity": [1.0, -1.0, 0.5]}' > "$tmp/id.json"
"$FRIG_CLI" --quiet model export --model "$FRIG_TEST_MODEL" --identity "$tmp/id.json" -o "$tmp/out" >/dev/null || exit 1
# With a face texture (a PNG made here, as the sfs stage would write WORKSPACE/textures/albedo.png)
# and with the eye overlays left out.
python3 "$FRIG_SOURCE_DIR/tests/scripts/make_png.py" "$tmp/albedo.png" 256 256 || exit 1
"$FRIG_CLI" --quiet model export --model "$FRIG_TEST_MODEL" --texture "$tmp/albedo.png" -o "$tmp/tex.glb" >/dev/null || exit 1
"$FRIG_CLI" --quiet --set export.eye_overlays=0 model export --model "$FRIG_TEST_MODEL" -o "$tmp/noov.glb" >/dev/null || exit 1
fail=0
for f in "$tmp/out/rig.glb" "$tmp/tex.glb" "$tmp/noov.glb"; do
  echo "$(basename "$f"):"
  node "$FRIG_SOURCE_DIR/tests/scripts/gltf_validate.js" "$tools" "$f" || fail=1
done
exit $fail
