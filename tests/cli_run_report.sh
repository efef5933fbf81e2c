#!/usr/bin/env bash
# frig run's report page on a small synthetic set: every picture and link it names exists
# beside it, it has its sections, thumbnails and plots, and headless Chromium opens it from
# disk with no console errors and no network request (a screenshot is kept in the build tree).
# A video input goes through ffmpeg into frames and the same pipeline.
set -u
. "$FRIG_SOURCE_DIR/tests/scripts/model_fixture.sh"
fail=0
check() { if ! eval "$1"; then echo "FAILED: $1"; fail=1; fi; }
F="$FRIG_CLI"
tmp="$FRIG_BINARY_DIR/test-tmp/cli_run_report"; rm -rf "$tmp"; mkdir -p "$tmp"
. "$FRIG_SOURCE_DIR/tests/scripts/scratch.sh"
frig_test_model || frig_test_skip "no ICT-FaceKit data"
[ -f /usr/share/dlib/shape_predictor_68_face_landmarks.dat ] || frig_test_skip "libdlib-data is not installed"
command -v chromium > /dev/null || frig_test_skip "chromium is not installed (scripts/install-deps.sh --test)"
command -v ffmpeg > /dev/null || frig_test_skip "ffmpeg is not installed (scripts/install-deps.sh --test)"
M="$FRIG_TEST_MODEL"
"$F" --quiet --set synth.image_size=256 --set synth.max_yaw=30 --set synth.failure_rate=0.15 --set synth.rig_obj=0 \
  synth --model "$M" -o "$tmp/synth" --photos 8 --seed 11 > /dev/null || exit 1
photos="$tmp/synth/subject_00/photos"
# The same photos as a video (MJPEG in Matroska: a codec every ffmpeg build has), 2 copies of each frame.
# Default detection (face-api's SSD where installed, so the identity step has descriptors).
ffmpeg -nostdin -v error -framerate 4 -i "$photos/photo_%03d.jpg" -vf "fps=8" -c:v mjpeg -q:v 3 "$tmp/clip.mkv" || exit 1

# A coarse sfs and one outer round keep it quick (cli_run and cli_retarget run two).
O=(--set fit.outline_iterations=4 --set export.texture_size=64 --set sfs.texture_size=128 --set sfs.shape_size=64 --set sfs.face_px=100 --set retarget.iterations=1
   --set sfs.rounds=3 --set sfs.pose_levels=0 --set sfs.stereo=0 --set sfs.joint_albedo=0 --set sfs.shape_iterations=4
   --set sfs.shape_sigma=0.03)
"$F" --threads 2 "${O[@]}" --set run.video_frames=8 run "$photos" "$tmp/clip.mkv" --model "$M" \
  -o "$tmp/out" > "$tmp/run.out" 2> "$tmp/run.err"
check '[ $? = 0 ]'
cat "$tmp/run.err"
check 'grep -q "^report: $tmp/out/report.html$" "$tmp/run.out"'
check '[ $(ls "$tmp/out/frames/clip" | grep -c "^clip_[0-9]*\.jpg$") = 8 ]'
check 'grep -q "frames .*1 video, 8 frames each" "$tmp/run.err"'

/usr/bin/python3 - "$tmp/out" > "$tmp/page" 2>&1 <<'PY'
import os, re, sys, json
out = sys.argv[1]
html = open(os.path.join(out, "report.html"), encoding="utf-8").read()
bad = []
refs = re.findall(r'(?:src|href)="([^"#][^"]*)"', html)
for ref in refs:
    if re.match(r"[a-z]+:", ref):
        bad.append("an absolute URL: " + ref)
        continue
    path = os.path.join(out, re.sub(r"%([0-9A-F]{2})", lambda m: chr(int(m.group(1), 16)), ref))
    if not os.path.exists(path):
        bad.append("missing: " + ref)
report = json.load(open(os.path.join(out, "report.json")))
n = len(report["photos"])
thumbs = len(re.findall(r'src="report/thumbs/\d+\.jpg"', html))
for need in ('id="rig"', 'id="errors"', 'id="coverage"', 'id="stages"', 'id="photos"', 'class="expr"', "report/expressions.png",
             "report/neutral_front.png", "Landmark error", "Fit error per photo", "<svg", 'id="shape"',
             "overlays/retarget/rigs.png", "textures/albedo.png", "Shape-from-shading error per photo",
             "Cloud distance to the personalized rig", 'src="report/sfs/', ">shape from shading</a>",
             "sfs and retargeting included"):
    if need not in html:
        bad.append("no " + need)
# Fewer than 9 photos used (RUN_FEW_PHOTOS): the report says so, and only then.
used = sum(1 for p in report["photos"] if p["status"] == "ok" and "fit" in p)
if ("<b>Few photos:</b> only %d photos were used" % used in html) != (used < 9):
    bad.append("%d photos used: the few-photos note %s" % (used, "missing" if used < 9 else "shown"))
if n != 16 or thumbs < n - 3:
    bad.append("%d photos, %d thumbnails" % (n, thumbs))
print("\n".join(bad) if bad else "page ok: %d photos (%d used), %d thumbnails, %d links" % (n, used, thumbs, len(refs)))
PY
cat "$tmp/page"
check 'grep -q "^page ok" "$tmp/page"'

# Headless Chromium, from disk: no console messages at error level, no network.
HOME="$tmp" timeout 120 chromium --headless=new --no-sandbox --disable-gpu --no-first-run --disable-extensions \
  --disable-background-networking --user-data-dir="$tmp/chromium" --enable-logging=stderr --v=0 \
  --window-size=1400,2400 --screenshot="$tmp/report.png" "file://$tmp/out/report.html" > /dev/null 2> "$tmp/chromium.log"
check '[ -s "$tmp/report.png" ]'
grep "CONSOLE" "$tmp/chromium.log" | head
check '! grep "CONSOLE" "$tmp/chromium.log" | grep -qi "error\|failed"'
check '! grep -qi "net::ERR\|Failed to load resource" "$tmp/chromium.log"'
# On a terminal: one bar redrawn in place, with the stage, its step, item i of n and the time.
if command -v script > /dev/null; then
  script -qec "'$F' --threads 2 ${O[*]} --set export.eye_overlays=0 --set run.video_frames=8 run '$photos' '$tmp/clip.mkv' --model '$M' -o '$tmp/out'" /dev/null > "$tmp/tty" 2>&1
  check 'grep -q "\[9/9 report\] contact_sheet *\[[#.]*\] [0-9]*/56  0:[0-9][0-9]" "$tmp/tty"'
  check 'grep -q "identity .*up to date" "$tmp/tty" && ! grep -q "export .*up to date" "$tmp/tty"'
fi
# A run that stops (here at sfs: no cloud kept) links no rig.glb, though an earlier run left one in
# the folder, and says why.
"$F" --threads 2 "${O[@]}" --set run.video_frames=8 --set sfs.min_points=1000000000 run "$photos" "$tmp/clip.mkv" \
  --model "$M" -o "$tmp/out" > /dev/null 2> "$tmp/stop.err"
check '[ $? = 1 ] && grep -q "stopped: 0 of" "$tmp/stop.err" && [ -f "$tmp/out/rig.glb" ]'
check 'grep -q "No rig was exported: the run stopped before the export stage" "$tmp/out/report.html"'
check '! grep -q "The rig: <a href=\"rig.glb\"" "$tmp/out/report.html" && grep -q "The run stopped:</b> 0 of" "$tmp/out/report.html"'
exit $fail
