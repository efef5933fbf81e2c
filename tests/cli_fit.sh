#!/usr/bin/env bash
# The stages end to end on synthetic photos: frig synth -> frig detect -> frig fit ->
# frig export. Statuses in report.json (the intended no-face photo has none), a fit for
# each usable photo, overlays, the rig files, and the errors: no workspace, no report, no
# model, a report without usable photos.
set -u
. "$FRIG_SOURCE_DIR/tests/scripts/model_fixture.sh"
fail=0
check() { if ! eval "$1"; then echo "FAILED: $1"; fail=1; fi; }
F="$FRIG_CLI"
py=/usr/bin/python3
tmp="$FRIG_BINARY_DIR/test-tmp/cli_fit"; rm -rf "$tmp"; mkdir -p "$tmp"
. "$FRIG_SOURCE_DIR/tests/scripts/scratch.sh"

check '"$F" help fit | grep -q "usage: frig fit -w WORKSPACE"'
check '"$F" help export | grep -q "usage: frig export -w WORKSPACE -o OUT"'
"$F" fit 2>/dev/null; check '[ $? = 2 ]'
"$F" fit -w "$tmp/empty" --model "$tmp/none.frigmodel" 2>"$tmp/err"; check '[ $? = 1 ]'
check 'grep -q "none.frigmodel" "$tmp/err"'

frig_test_model || frig_test_skip "no ICT-FaceKit data"
M="$FRIG_TEST_MODEL"
"$F" --quiet fit -w "$tmp/empty" --model "$M" 2>"$tmp/err"; check '[ $? = 1 ]'
check 'grep -q "no report.json yet" "$tmp/err"'

# 12 photos of one synthetic subject, 6 of them intended failures (one of each kind: occluder, extreme
# pose, no face, sunglasses, under- and over-exposed).
"$F" --quiet --set synth.image_size=320 --set synth.max_yaw=35 --set synth.failure_rate=0.5 --set synth.rig_obj=0 \
  synth --model "$M" -o "$tmp/synth" --photos 12 --seed 5 > /dev/null
check '[ $? = 0 ]'
"$F" --quiet detect "$tmp/synth/subject_00/photos" -w "$tmp/ws"
check '[ $? = 0 ]'
"$F" --quiet fit -w "$tmp/ws" --model "$M" 2>"$tmp/err"
check '[ $? = 0 ]'
cat "$tmp/err"
summary=$($py - "$tmp/ws/report.json" "$tmp/synth/subject_00/truth" <<'PY'
import json, sys, os
r = json.load(open(sys.argv[1]))
fitted = [p for p in r["photos"] if "fit" in p]
nofit_ok = [p for p in r["photos"] if p["status"] == "ok" and "fit" not in p]
# the intended no-face photo must not be fitted
noface = []
for p in r["photos"]:
    t = json.load(open(os.path.join(sys.argv[2], os.path.basename(p["file"]).replace(".jpg", ".json"))))
    if t.get("failure") == "no_face":
        noface.append(p["status"])
errs = sorted(p["fit"]["reprojection_error_px"] for p in fitted)
print(len(fitted), len(nofit_ok), len(r["fit"]["identity"]), len(r["fit"]["expressions"]),
      ",".join(noface), "%.2f" % errs[len(errs) // 2])
PY
)
echo "fitted, ok-but-unfitted, identity, expressions, no-face statuses, median error px: $summary"
read nfit nunfit nid nexp noface med <<< "$summary"
check '[ "$nfit" -ge 5 ] && [ "$nunfit" = 0 ] && [ "$nid" = 100 ] && [ "$nexp" = 53 ]'
check '[ "$noface" = "no_face" ]'
check "$py -c 'import sys; sys.exit(0 if float(\"$med\") < 6 else 1)'"
check '[ $(ls "$tmp/ws/overlays/fit" | grep -c "\.jpg$") = "$nfit" ]'
check '[ -s "$tmp/ws/rig/rig.frigrig" ]'

"$F" --quiet export -w "$tmp/ws" -o "$tmp/out" > "$tmp/exp"
check '[ $? = 0 ]'
check '[ -s "$tmp/out/rig.glb" ] && [ -s "$tmp/out/shapes/neutral.obj" ] && [ -s "$tmp/out/shapes/jawOpen.obj" ]'
check 'grep -q "ARKit names not provided: tongueOut" "$tmp/exp"'
# WORKSPACE/textures/albedo.png (the sfs stage's) becomes the face's texture; --no-texture skips it.
mkdir -p "$tmp/ws/textures" && python3 "$FRIG_SOURCE_DIR/tests/scripts/make_png.py" "$tmp/ws/textures/albedo.png" 64 64
"$F" --quiet export -w "$tmp/ws" -o "$tmp/tex.glb" > "$tmp/exp"
check '[ $? = 0 ] && grep -q "face texture .*albedo.png" "$tmp/exp" && cmp -s "$tmp/ws/textures/albedo.png" "$tmp/tex_shapes/frig_face.png"'
check '! cmp -s "$tmp/tex.glb" "$tmp/out/rig.glb"'
"$F" --quiet export -w "$tmp/ws" -o "$tmp/notex.glb" --no-texture > /dev/null
check 'cmp -s "$tmp/notex.glb" "$tmp/out/rig.glb" && [ ! -e "$tmp/notex_shapes/frig_face.png" ]'
rm -r "$tmp/ws/textures"
# Without the rig file, export makes the rig from the model and the fitted identity: same glb.
mv "$tmp/ws/rig/rig.frigrig" "$tmp/rig.bak"
"$F" --quiet export -w "$tmp/ws" -o "$tmp/out2" --model "$M" > /dev/null
check '[ $? = 0 ] && cmp -s "$tmp/out/rig.glb" "$tmp/out2/rig.glb"'
exit $fail
