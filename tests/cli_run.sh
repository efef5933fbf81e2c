#!/usr/bin/env bash
# frig run on a synthetic subject: the whole pipeline (sfs and retarget with its outer loop
# included), then what a rerun keeps (nothing changed: every stage up to date, no file
# rewritten; another export option: only export and the report run; another fit option: fit and
# what follows; another sfs option: sfs, retarget, export), a run killed (SIGKILL) at random
# points and resumed until done giving byte-identical rig.glb, shapes/ and clouds/ to the clean run, a "full disk"
# (a file-size limit) and a resume, too few photos or clouds (a sentence and exit 1, again on a rerun), -o NAME.glb, inputs
# left untouched, and the usage errors.
set -u
. "$FRIG_SOURCE_DIR/tests/scripts/model_fixture.sh"
fail=0
check() { if ! eval "$1"; then echo "FAILED: $1"; fail=1; fi; }
F="$FRIG_CLI"
tmp="$FRIG_BINARY_DIR/test-tmp/cli_run"; rm -rf "$tmp"; mkdir -p "$tmp"
. "$FRIG_SOURCE_DIR/tests/scripts/scratch.sh"

check '"$F" help run | grep -q "usage: frig run PHOTO|FOLDER|VIDEO"'
"$F" run 2>/dev/null; check '[ $? = 2 ]'
"$F" run "$tmp/nothing_here" -o "$tmp/x" 2>"$tmp/err"; check '[ $? = 1 ]'
check 'grep -q "nothing_here: no such file or folder" "$tmp/err"'

frig_test_model || frig_test_skip "no ICT-FaceKit data"
[ -f /usr/share/dlib/shape_predictor_68_face_landmarks.dat ] || frig_test_skip "libdlib-data is not installed"
M="$FRIG_TEST_MODEL"
"$F" --quiet --set synth.image_size=256 --set synth.max_yaw=30 --set synth.failure_rate=0.1 --set synth.rig_obj=0 \
  synth --model "$M" -o "$tmp/synth" --photos 10 --seed 7 > /dev/null || exit 1
photos="$tmp/synth/subject_00/photos"
before=$(cd "$photos" && sha256sum * | sha256sum)
# The report and the SSD detector are tested by cli_run_report.sh (and identity's tests); here the
# cascades (detect.detector=1), small textures, a coarse sfs (the shared shape as before 2026-12-02:
# 3 alternated rounds, no registration), one outer round (two, recovering the
# clouds in the loop, in the kill test), four outline steps in the fit and --no-report keep a dozen runs
# quick under ASan.
O=(--set detect.detector=1 --set fit.outline_iterations=4 --set export.texture_size=64 --set sfs.texture_size=128 --set sfs.shape_size=64
   --set sfs.face_px=100 --set retarget.iterations=1 --set sfs.rounds=3 --set sfs.pose_levels=0 --set sfs.stereo=0
   --set sfs.joint_albedo=0 --set sfs.shape_iterations=4 --set sfs.shape_sigma=0.03)
run() { "$F" --threads 2 "${O[@]}" "${@:2}" run "$photos" --model "$M" --no-report -o "$1"; }

# A clean run.
run "$tmp/clean" > "$tmp/clean.out" 2> "$tmp/clean.err"; check '[ $? = 0 ]'
cat "$tmp/clean.err"
check '[ -s "$tmp/clean/rig.glb" ] && [ -f "$tmp/clean/shapes/neutral.obj" ] && [ -s "$tmp/clean/report.json" ]'
check 'grep -q "^rig: $tmp/clean/rig.glb and $tmp/clean/shapes/$" "$tmp/clean.out"'
for s in detect identity filter fit sfs retarget export; do check '[ -s "$tmp/clean/stages/'$s'/stage.json" ]'; done
# sfs and retarget: clouds, the albedo as rig.glb's face texture, the rigs sheet, two outer rounds
check '[ $(ls "$tmp/clean/clouds" | grep -c "^photo_[0-9]*\.ply$") -ge 5 ] && [ -s "$tmp/clean/textures/albedo.png" ]'
check '[ -s "$tmp/clean/overlays/retarget/rigs.png" ] && [ -n "$(ls "$tmp/clean/overlays/sfs")" ]'
check 'grep -q "retarget .*1 round (clouds recovered 0 times more)" "$tmp/clean.err"'
check 'cmp -s "$tmp/clean/textures/albedo.png" "$tmp/clean/stages/sfs/albedo.png"'   # no recovery: sfs's albedo
check 'grep -aq "\"image/png\"" "$tmp/clean/rig.glb"'
check '! cmp -s "$tmp/clean/stages/fit/rig.frigrig" "$tmp/clean/rig/rig.frigrig"'   # the personalized rig, not the fit's
check '[ ! -e "$tmp/clean/stages/frames" ] && [ ! -e "$tmp/clean/stages/detect/partial" ]'
check '[ "$(cd "$photos" && sha256sum * | sha256sum)" = "$before" ]'   # inputs untouched
mkdir -p "$tmp/ref" && cp -r "$tmp/clean/rig.glb" "$tmp/clean/shapes" "$tmp/clean/clouds" "$tmp/clean/stages" "$tmp/ref/"

# Nothing changed: every stage up to date, the rig not rewritten.
stamp=$(stat -c %Y.%y "$tmp/clean/rig.glb")
run "$tmp/clean" > /dev/null 2> "$tmp/again.err"; check '[ $? = 0 ]'
check '[ $(grep -c "up to date" "$tmp/again.err") = 7 ] && [ "$(stat -c %Y.%y "$tmp/clean/rig.glb")" = "$stamp" ]'
# Another export option: detect, filter and fit are kept.
cp "$tmp/clean/rig.glb" "$tmp/base.glb"
run "$tmp/clean" --set export.eye_overlays=0 > /dev/null 2> "$tmp/ov.err"; check '[ $? = 0 ]'
check 'grep -q "detect .*up to date" "$tmp/ov.err" && grep -q "fit .*up to date" "$tmp/ov.err" && ! grep -q "export .*up to date" "$tmp/ov.err"'
check '! cmp -s "$tmp/clean/rig.glb" "$tmp/base.glb"'
# Another fit option: fit and what follows run again, detect and filter are kept.
run "$tmp/clean" --set fit.w_id=25 > /dev/null 2> "$tmp/fit.err"; check '[ $? = 0 ]'
check 'grep -q "filter .*up to date" "$tmp/fit.err" && ! grep -q "fit .*up to date" "$tmp/fit.err"'
cp "$tmp/clean/rig.glb" "$tmp/changed.glb" && rm -rf "$tmp/changed_clouds" && cp -r "$tmp/clean/clouds" "$tmp/changed_clouds"
# Another sfs option too: sfs and retarget run again (and export, the rig having changed), fit is kept.
run "$tmp/clean" --set fit.w_id=25 --set sfs.e_max=0.06 > /dev/null 2> "$tmp/sfs.err"; check '[ $? = 0 ]'
check 'grep -q "fit .*up to date" "$tmp/sfs.err" && ! grep -q "sfs .*up to date" "$tmp/sfs.err" && ! grep -q "retarget .*up to date" "$tmp/sfs.err"'
check '! diff -rq "$tmp/clean/clouds" "$tmp/changed_clouds" > /dev/null && ! cmp -s "$tmp/clean/rig.glb" "$tmp/changed.glb"'
# Back to the defaults: the clean run's bytes again.
run "$tmp/clean" > /dev/null 2>&1; check '[ $? = 0 ]'
check 'cmp -s "$tmp/clean/rig.glb" "$tmp/ref/rig.glb" && diff -rq "$tmp/clean/shapes" "$tmp/ref/shapes" && ! cmp -s "$tmp/changed.glb" "$tmp/ref/rig.glb"'
check 'diff -rq "$tmp/clean/clouds" "$tmp/ref/clouds"'
# A full disk (a file-size limit the glTF cannot fit in) while export runs again (its record
# removed): an error sentence, exit 1; then resumed: export alone, the same bytes.
rm "$tmp/clean/stages/export/stage.json"
( ulimit -f 4000; trap "" XFSZ; exec "$F" --threads 2 "${O[@]}" run "$photos" --model "$M" --no-report -o "$tmp/clean" ) > /dev/null 2> "$tmp/full.err"
check '[ $? = 1 ] && grep -q "File too large\|write failed" "$tmp/full.err"'
run "$tmp/clean" > /dev/null 2> "$tmp/full2.err"; check '[ $? = 0 ]'
check 'grep -q "retarget .*up to date" "$tmp/full2.err" && ! grep -q "export .*up to date" "$tmp/full2.err"'
check 'cmp -s "$tmp/clean/rig.glb" "$tmp/ref/rig.glb" && diff -rq "$tmp/clean/shapes" "$tmp/ref/shapes"'

# Killed (SIGKILL) at random points and resumed until done: the same bytes as a clean run
# (bench/kill_resume.sh, the benchmark's kill test, on this small set; 3 kills), with two outer
# rounds: the clouds recovered with the personalized rig inside retarget.
bash "$FRIG_SOURCE_DIR/bench/kill_resume.sh" "$photos" "$tmp/kr" 3 13 -- --model "$M" "${O[@]}" --set retarget.iterations=2 \
  > "$tmp/kr.out" 2>&1
check '[ $? = 0 ]'
cat "$tmp/kr.out"
# Up to 3 kills: each comes after a share of the work the clean run's stage times say is left, so
# on a machine whose load falls between the runs the resumed run can finish first (then fewer).
check 'grep -Eq "^[1-3] kills; rig.glb, shapes/ and clouds/ byte-identical to the clean run$" "$tmp/kr.out"'
check 'grep -q "retarget .*2 rounds (clouds recovered 1 times more)" "$tmp/kr/clean.log"'
check '! cmp -s "$tmp/kr/clean/textures/albedo.png" "$tmp/kr/clean/stages/sfs/albedo.png"'   # the recovered albedo
check '! diff -rq "$tmp/kr/clean/clouds" "$tmp/ref/clouds" > /dev/null'   # the clouds recovered in the loop
check '[ -z "$(find "$tmp/kr/killed" "$tmp/clean" -name ".*.??????")" ]'   # no temporary files left

# Too few usable photos: a sentence naming how many and why, exit 1.
mkdir -p "$tmp/few" && cp "$photos/photo_000.jpg" "$photos/photo_001.jpg" "$tmp/few/" && cp "$photos/photo_001.jpg" "$tmp/few/copy.jpg"
"$F" --threads 2 "${O[@]}" run "$tmp/few" --model "$M" --no-report -o "$tmp/fewout" > /dev/null 2> "$tmp/few.err"; check '[ $? = 1 ]'
cat "$tmp/few.err" | tail -1
check 'grep -q "stopped: 2 of 3 photos are usable after detect, and a rig needs at least 5 (run.min_photos): 1 duplicate" "$tmp/few.err"'
check '[ ! -e "$tmp/fewout/rig.glb" ]'
# Another build of frig (here its bytes and one byte more, which an ELF program ignores) does not
# take the records of this one as up to date; the same build does.
"$F" --threads 2 "${O[@]}" run "$tmp/few" --model "$M" --no-report -o "$tmp/fewout" > /dev/null 2> "$tmp/few_same.err"
check '[ $? = 1 ] && grep -q "detect .*up to date" "$tmp/few_same.err" && grep -q "stopped: 2 of 3 photos are usable after detect" "$tmp/few_same.err"'
# Photos whose shading does not read (here: every cloud under sfs.min_points) stop the run after
# sfs (run.min_cloud_share), and again when the same command runs again (the stop is in sfs's record).
few2=(--set run.min_photos=2 --set sfs.min_points=1000000000)
"$F" --threads 2 "${O[@]}" "${few2[@]}" run "$tmp/few" --model "$M" --no-report -o "$tmp/fewsfs" > /dev/null 2> "$tmp/fewsfs.err"
check '[ $? = 1 ] && grep -q "stopped: 0 of 2 fitted photos kept a point cloud, under run.min_cloud_share (0.5)" "$tmp/fewsfs.err"'
check '[ ! -e "$tmp/fewsfs/rig.glb" ]'
"$F" --threads 2 "${O[@]}" "${few2[@]}" run "$tmp/few" --model "$M" --no-report -o "$tmp/fewsfs" > /dev/null 2> "$tmp/fewsfs2.err"
check '[ $? = 1 ] && grep -q "sfs .*up to date" "$tmp/fewsfs2.err" && grep -q "stopped: 0 of 2 fitted" "$tmp/fewsfs2.err"'
cp "$F" "$tmp/frig_other" && printf x >> "$tmp/frig_other"
"$tmp/frig_other" --threads 2 "${O[@]}" run "$tmp/few" --model "$M" --no-report -o "$tmp/fewout" > /dev/null 2> "$tmp/few_other.err"
check '[ $? = 1 ] && ! grep -q "up to date" "$tmp/few_other.err" && grep -q "stopped: 2 of 3 photos" "$tmp/few_other.err"'
# With run.min_photos 2 they make a rig. Two runs in one folder at once: the second says so and
# leaves the first alone. With -o NAME.glb: that file, NAME_shapes/ beside it, the run's folder
# NAME_run/.
( exec "$F" --threads 2 "${O[@]}" --set run.min_photos=2 run "$tmp/few" --model "$M" --no-report -o "$tmp/named/face.glb" ) \
  > /dev/null 2>&1 &
pid=$!
sleep 0.5
"$F" --threads 2 "${O[@]}" --set run.min_photos=2 run "$tmp/few" --model "$M" --no-report -o "$tmp/named/face.glb" \
  > /dev/null 2> "$tmp/busy.err"
check '[ $? = 1 ] && grep -q "another frig run is working in $tmp/named/face_run" "$tmp/busy.err"'
wait $pid; check '[ $? = 0 ]'
check '[ -s "$tmp/named/face.glb" ] && [ -f "$tmp/named/face_shapes/jawOpen.obj" ] && [ -s "$tmp/named/face_run/report.json" ]'
check '[ ! -e "$tmp/named/face_run/rig.glb" ] && [ "$(ls "$tmp/named/face_run/clouds" | grep -c "\.ply$")" = 2 ]'
# Its report (the other stages up to date) says that 2 photos are few for the shape.
"$F" --threads 2 "${O[@]}" --set run.min_photos=2 run "$tmp/few" --model "$M" -o "$tmp/named/face.glb" > /dev/null \
  2> "$tmp/few_report.err"
check '[ $? = 0 ] && grep -q "2 used (few for the shape: see the report.s note)" "$tmp/few_report.err"'
check 'grep -q "<b>Few photos:</b> only 2 photos were used for the rig" "$tmp/named/face_run/report.html"'
exit $fail
