#!/usr/bin/env bash
# frig synth: the data set's files and index, the same bytes from the same seed whatever
# --threads is, the OBJ switch, and the errors: bad arguments, a missing model.
set -u
. "$FRIG_SOURCE_DIR/tests/scripts/model_fixture.sh"
fail=0
check() { if ! eval "$1"; then echo "FAILED: $1"; fail=1; fi; }
F="$FRIG_CLI"
tmp="$FRIG_BINARY_DIR/test-tmp/cli_synth"; rm -rf "$tmp"; mkdir -p "$tmp"
. "$FRIG_SOURCE_DIR/tests/scripts/scratch.sh"

check '"$F" help synth | grep -q "frig synth \[--model FILE\] -o DIR"'
"$F" synth 2>/dev/null; check '[ $? = 2 ]'
"$F" synth -o "$tmp/x" --photos -1 2>"$tmp/err"; check '[ $? = 2 ]'
check 'grep -q "photos wants a whole number" "$tmp/err"'
"$F" synth -o "$tmp/x" --seed abc 2>/dev/null; check '[ $? = 2 ]'
"$F" synth --model "$tmp/none.frigmodel" -o "$tmp/x" 2>"$tmp/err"; check '[ $? = 1 ]'
check 'grep -q "none.frigmodel" "$tmp/err"'

frig_test_model || frig_test_skip "no ICT-FaceKit data"
M="$FRIG_TEST_MODEL"
set_small="--set synth.image_size=96 --set synth.failure_rate=0.5"
"$F" --quiet --threads 1 $set_small --set synth.rig_obj=0 synth --model "$M" -o "$tmp/a" --photos 4 --seed 9 > "$tmp/out"
check '[ $? = 0 ]'
check 'grep -q "1 subject x 4 photos (2 intended failures each), seed 9" "$tmp/out"'
check '[ -f "$tmp/a/index.json" ] && [ -f "$tmp/a/subject_00/subject.json" ]'
check '[ -f "$tmp/a/subject_00/rig/rig.frigrig" ] && [ -s "$tmp/a/subject_00/rig/rig.glb" ] && [ ! -d "$tmp/a/subject_00/rig/shapes" ]'
check '[ $(ls "$tmp/a/subject_00/photos" | grep -c "\.jpg$") = 4 ]'
check '[ $(ls "$tmp/a/subject_00/truth" | grep -c "\.json$") = 4 ]'
# 96 x 96 float32 depth maps
check '[ $(stat -c %s "$tmp/a/subject_00/truth/photo_000.depth.f32") = 36864 ]'
check '"$F" info "$tmp/a/subject_00/photos/photo_003.jpg" | grep -q "96x96, 3 channels, 8-bit, orientation 1, JPEG"'
check '[ $(grep -c "\"failure\": \"none\"" "$tmp/a/index.json") = 2 ]'
"$F" --quiet --threads 2 $set_small --set synth.rig_obj=0 synth --model "$M" -o "$tmp/b" --photos 4 --seed 9 >/dev/null
check 'diff -r -q "$tmp/a" "$tmp/b" >/dev/null'
"$F" --quiet $set_small synth --model "$M" -o "$tmp/c" --photos 1 --seed 9 >/dev/null
check '[ -f "$tmp/c/subject_00/rig/shapes/neutral.obj" ] && [ -f "$tmp/c/subject_00/rig/shapes/jawOpen.obj" ]'
rm -rf "$tmp"
exit $fail
