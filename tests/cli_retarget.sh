#!/usr/bin/env bash
# frig retarget end to end on synthetic photos: synth -> detect -> filter -> fit -> clouds from
# the true depth (bench/truth_clouds) -> retarget --fixed-clouds (2 outer rounds) -> export,
# scored per vertex against the true rig (bench/score_shapes): the personalized neutral is
# nearer the truth than the fit's model-space rig; the report has the rounds. Then the outer
# loop with the sfs stage: fit -> sfs -> retarget (2 rounds, the clouds and the albedo
# recovered with the new rig) -> export, textured with that albedo. Errors: no workspace, no
# rig, no clouds.
set -u
. "$FRIG_SOURCE_DIR/tests/scripts/model_fixture.sh"
fail=0
check() { if ! eval "$1"; then echo "FAILED: $1"; fail=1; fi; }
F="$FRIG_CLI"
py=/usr/bin/python3
B="$FRIG_BINARY_DIR/bench"
tmp="$FRIG_BINARY_DIR/test-tmp/cli_retarget"; rm -rf "$tmp"; mkdir -p "$tmp"
. "$FRIG_SOURCE_DIR/tests/scripts/scratch.sh"

check '"$F" help retarget | grep -q "usage: frig retarget -w WORKSPACE"'
"$F" retarget 2>/dev/null; check '[ $? = 2 ]'
"$F" retarget -w "$tmp/ws" --iterations 0 2>/dev/null; check '[ $? = 2 ]'

frig_test_model || frig_test_skip "no ICT-FaceKit data"
M="$FRIG_TEST_MODEL"
[ -x "$B/truth_clouds" ] && [ -x "$B/score_shapes" ] || frig_test_skip "the bench programs are not built"

"$F" --quiet --set synth.image_size=320 --set synth.max_yaw=35 --set synth.failure_rate=0 --set synth.rig_obj=0 \
  synth --model "$M" -o "$tmp/synth" --photos 10 --seed 7 > /dev/null
check '[ $? = 0 ]'
"$F" --quiet detect "$tmp/synth/subject_00/photos" -w "$tmp/ws" && "$F" --quiet filter -w "$tmp/ws" &&
  "$F" --quiet fit -w "$tmp/ws" --model "$M" --no-overlays
check '[ $? = 0 ]'
cp -r "$tmp/ws" "$tmp/ws_sfs"
"$F" --quiet retarget -w "$tmp/ws" --model "$M" 2>"$tmp/err"; check '[ $? = 2 ]'
check 'grep -q "no point cloud" "$tmp/err"'
"$F" --quiet export -w "$tmp/ws" -o "$tmp/fit_out" > /dev/null
check '[ $? = 0 ]'
"$B/truth_clouds" "$tmp/ws" > /dev/null
check '[ $? = 0 ] && [ $(ls "$tmp/ws/clouds" | grep -c "\.ply$") -ge 5 ]'
"$F" --threads 2 retarget -w "$tmp/ws" --model "$M" --iterations 2 --fixed-clouds 2>"$tmp/log"
check '[ $? = 0 ]'
cat "$tmp/log"
check 'grep -q "round 2" "$tmp/log"'
"$F" --quiet export -w "$tmp/ws" -o "$tmp/out" > /dev/null
check '[ $? = 0 ] && [ -s "$tmp/out/rig.glb" ] && [ -s "$tmp/out/shapes/neutral.obj" ]'
rounds=$($py -c 'import json,sys; r=json.load(open(sys.argv[1])); print(len(r["retarget"]["rounds"]), sum(1 for p in r["photos"] if "retarget" in p))' "$tmp/ws/report.json")
echo "rounds, photos retargeted: $rounds"
read nr np <<< "$rounds"
check '[ "$nr" = 2 ] && [ "$np" -ge 5 ]'
truth="$tmp/synth/subject_00/rig/rig.frigrig"
fit_score=$("$B/score_shapes" "$tmp/fit_out/shapes" "$truth")
rt_score=$("$B/score_shapes" "$tmp/out/shapes" "$truth" "$M")
echo "$fit_score"; echo "$rt_score"
f_aligned=$(echo "$fit_score" | sed -n 's/.*(aligned \([0-9.]*\)).*/\1/p')
r_aligned=$(echo "$rt_score" | head -1 | sed -n 's/.*(aligned \([0-9.]*\)).*/\1/p')
# Measured: model-space 4.6 mm -> personalized 3.4 mm (aligned, face region); floor 0.85 of the fit's.
check "$py -c 'import sys; sys.exit(0 if float(\"$r_aligned\") < 0.85 * float(\"$f_aligned\") else 1)'"

# The outer loop with the sfs stage recovering the clouds each round.
# A coarse sfs (as cli_run's) keeps it quick: what is checked here is the loop, not the clouds' error.
w="$tmp/ws_sfs"
SO=(--set sfs.texture_size=128 --set sfs.shape_size=64 --set sfs.face_px=100 --set sfs.rounds=3 --set sfs.pose_levels=0
    --set sfs.stereo=0 --set sfs.joint_albedo=0 --set sfs.shape_iterations=4 --set sfs.shape_sigma=0.03)
"$F" --quiet --threads 2 "${SO[@]}" sfs -w "$w" --no-overlays --model "$M"
check '[ $? = 0 ] && [ -s "$w/textures/albedo.png" ]'
check '$py -c "import json,sys; r=json.load(open(sys.argv[1])); sys.exit(0 if \"identity\" in r[\"sfs\"] else 1)" "$w/report.json"'
sum_before=$(cat "$w"/clouds/*.ply | md5sum)
"$F" --threads 2 "${SO[@]}" retarget -w "$w" --model "$M" --iterations 2 2>"$tmp/log_sfs"
check '[ $? = 0 ]'
cat "$tmp/log_sfs"
check 'grep -q "round 2" "$tmp/log_sfs"'
check '[ "$(cat "$w"/clouds/*.ply | md5sum)" != "$sum_before" ]'   # recovered with the new rig
rounds=$($py -c 'import json,sys; r=json.load(open(sys.argv[1])); print(len(r["retarget"]["rounds"]), sum(1 for p in r["photos"] if "retarget" in p))' "$w/report.json")
read nr np <<< "$rounds"
check '[ "$nr" = 2 ] && [ "$np" -ge 3 ]'
# the recoveries took the light shared solve (retarget.sfs_light, the default), and the record says so
check '$py -c "import json,sys; b=json.load(open(sys.argv[1]))[\"sfs\"]; sys.exit(0 if (b[\"shared_solve\"], b[\"why\"]) == (\"light\", \"outer_loop\") else 1)" "$w/report.json"'
# each round started from the identity its clouds were drawn at, and used it: none is left over
check '$py -c "import json,sys; r=json.load(open(sys.argv[1])); sys.exit(0 if \"identity\" not in r[\"sfs\"] else 1)" "$w/report.json"'
"$F" --quiet export -w "$w" -o "$tmp/out_sfs" > /dev/null
check '[ $? = 0 ] && [ -s "$tmp/out_sfs/shapes/neutral.obj" ]'
# The glTF's face texture is the albedo the last recovery wrote, byte for byte.
$py - "$tmp/out_sfs/rig.glb" "$w/textures/albedo.png" <<'EOF'
import json, struct, sys
b = open(sys.argv[1], 'rb').read()
n = struct.unpack('<I', b[12:16])[0]
j = json.loads(b[20:20 + n])
img = [i for i in j['images'] if i['name'] == 'frig_face'][0]
v = j['bufferViews'][img['bufferView']]
start = 20 + n + 8 + v.get('byteOffset', 0)
sys.exit(0 if b[start:start + v['byteLength']] == open(sys.argv[2], 'rb').read() else 1)
EOF
check '[ $? = 0 ]'
rt_sfs=$("$B/score_shapes" "$tmp/out_sfs/shapes" "$truth")
echo "$rt_sfs"
exit $fail
