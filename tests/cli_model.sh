#!/usr/bin/env bash
# frig model import-ict / info / export: outputs, defaults ($FRIG_MODEL), identity JSON,
# and the errors: an edited ICT folder, a missing model, bad arguments.
set -u
. "$FRIG_SOURCE_DIR/tests/scripts/model_fixture.sh"
fail=0
check() { if ! eval "$1"; then echo "FAILED: $1"; fail=1; fi; }
F="$FRIG_CLI"
tmp="$FRIG_BINARY_DIR/test-tmp/cli_model"; rm -rf "$tmp"; mkdir -p "$tmp"
. "$FRIG_SOURCE_DIR/tests/scripts/scratch.sh"

check '"$F" help model | grep -q "frig model import-ict DIR"'
"$F" model 2>/dev/null; check '[ $? = 2 ]'
"$F" model frobnicate 2>/dev/null; check '[ $? = 2 ]'
"$F" model info --model "$tmp/none.frigmodel" 2>"$tmp/err"; check '[ $? = 1 ]'
check 'grep -q "none.frigmodel: no such file" "$tmp/err"'
FRIG_MODEL= XDG_DATA_HOME="$tmp/xdg" "$F" model info 2>"$tmp/err"; check '[ $? = 1 ]'
check 'grep -q "$tmp/xdg/frig/ict.frigmodel" "$tmp/err"'

frig_test_model || frig_test_skip "no ICT-FaceKit data"
ict="$FRIG_TEST_ICT"
# Import to the default path (through XDG_DATA_HOME, the folder is created).
XDG_DATA_HOME="$tmp/xdg" "$F" --quiet model import-ict "$ict" > "$tmp/out"; check '[ $? = 0 ]'
check 'grep -q "xdg/frig/ict.frigmodel: [0-9]* bytes" "$tmp/out"'
check 'cmp -s "$tmp/xdg/frig/ict.frigmodel" "$FRIG_TEST_MODEL"'
FRIG_MODEL="$FRIG_TEST_MODEL" "$F" model info > "$tmp/info"; check '[ $? = 0 ]'
check 'grep -q "vertices 26719, polygons 26384, triangles 52220, uvs 28911, materials 12" "$tmp/info"'
check 'grep -q "identity modes 100, expressions 57, landmarks 68, contour candidates 17 + 17, rigid vertices 1487" "$tmp/info"'
check 'grep -q "^  eyelashes_right *vertices 26035 .. 26718 (684)" "$tmp/info"'
check 'grep -q "^  jawOpen \*$" "$tmp/info"'
check 'grep -q "^  PupilDilate_L$" "$tmp/info"'

echo '{"identity": [2.0, 0, -1.5]}' > "$tmp/id.json"
"$F" --quiet model export --model "$FRIG_TEST_MODEL" --identity "$tmp/id.json" -o "$tmp/rig" > "$tmp/export"
check '[ $? = 0 ]'
check '[ -s "$tmp/rig/rig.glb" ] && [ -f "$tmp/rig/shapes/neutral.obj" ] && [ -f "$tmp/rig/shapes/frig.mtl" ]'
check '[ $(ls "$tmp/rig/shapes" | grep -c "\.obj$") = 56 ]'
check '[ -f "$tmp/rig/shapes/eyeBlinkLeft.obj" ] && [ -f "$tmp/rig/shapes/cheekPuff.obj" ] && [ -f "$tmp/rig/shapes/cheekRaiser_L.obj" ]'
check 'grep -q "^targets (55): eyeBlinkLeft .* browInnerUp .* PupilDilate_R$" "$tmp/export"'
check 'grep -q "^ARKit names not provided: tongueOut$" "$tmp/export"'
# The identity changes the neutral: not the mean face's.
"$F" --quiet model export --model "$FRIG_TEST_MODEL" -o "$tmp/mean" > /dev/null
check '! cmp -s "$tmp/rig/shapes/neutral.obj" "$tmp/mean/shapes/neutral.obj"'
check 'cmp -s <(grep "^f " "$tmp/rig/shapes/neutral.obj") <(grep "^f " "$tmp/mean/shapes/jawOpen.obj")'
echo '{"identity": [1, "x"]}' > "$tmp/bad.json"
"$F" model export --model "$FRIG_TEST_MODEL" --identity "$tmp/bad.json" -o "$tmp/x" 2>"$tmp/err"; check '[ $? = 2 ]'
check 'grep -q "identity weight 1 is not a number" "$tmp/err"'
"$F" model export --model "$FRIG_TEST_MODEL" 2>/dev/null; check '[ $? = 2 ]'
# -o NAME.glb writes that file and NAME_shapes/ beside it (not a folder named NAME.glb).
"$F" --quiet model export --model "$FRIG_TEST_MODEL" -o "$tmp/named/face.glb" > "$tmp/named.out"; check '[ $? = 0 ]'
check '[ -f "$tmp/named/face.glb" ] && [ -f "$tmp/named/face_shapes/neutral.obj" ] && [ -f "$tmp/named/face_shapes/frig_iris_left.png" ]'
check 'cmp -s "$tmp/named/face.glb" "$tmp/mean/rig.glb"'
check 'grep -q "^$tmp/named/face.glb and $tmp/named/face_shapes/ " "$tmp/named.out"'
"$F" model export --model "$FRIG_TEST_MODEL" -o "$tmp/named/face.gltf" 2>"$tmp/err"; check '[ $? = 2 ]'
check 'grep -q "give a NAME.glb or a folder" "$tmp/err"'
# The MTL names the painted textures and the overlays' transparency.
check 'grep -q "^map_Kd frig_sclera_left.png$" "$tmp/mean/shapes/frig.mtl" && grep -q "^d 0.12$" "$tmp/mean/shapes/frig.mtl"'

# An edited folder: a missing expression file fails with the file's name.
mkdir -p "$tmp/edited" && ln -s "$ict"/* "$tmp/edited/" && rm "$tmp/edited/mouthPucker.obj"
"$F" --quiet model import-ict "$tmp/edited" -o "$tmp/edited.frigmodel" 2>"$tmp/err"; check '[ $? = 1 ]'
check 'grep -q "mouthPucker.obj: missing from the ICT-FaceKit folder" "$tmp/err"'
check '[ ! -e "$tmp/edited.frigmodel" ]'
cat "$tmp/err"
exit $fail
