#!/usr/bin/env bash
# The exported rig.glb passes the Khronos glTF validator with 0 errors and 0 warnings.
# Needs node and gltf-validator in $FRIG_TOOLS_DIR (scripts/install-deps.sh --test).
set -u
. "$FRIG_SOURCE_DIR/tests/scripts/model_fixture.sh"
tools="${FRIG_TOOLS_DIR:-$FRIG_SOURCE_DIR/build/tools}"
command -v node >/dev/null || frig_test_skip "node is not installed (scripts/install-deps.sh --test)"
[ -f "$tools/node_modules/gltf-validator/package.json" ] ||
  frig_test_skip "gltf-validator is not in $tools (scripts/install-deps.sh --test)"
frig_test_model || frig_test_skip "no ICT-FaceKit data"
tmp="$FRIG_BINARY_DIR/test-tmp/cli_gltf_validator"; rm -rf "$tmp"; mkdir -p "$tmp"
echo '{"identity": [1.0, -1.0, 0.5]}' > "$tmp/id.json"
"$FRIG_CLI" --quiet model export --model "$FRIG_TEST_MODEL" --identity "$tmp/id.json" -o "$tmp/out" >/dev/null || exit 1
node "$FRIG_SOURCE_DIR/tests/scripts/gltf_validate.js" "$tools" "$tmp/out/rig.glb"
