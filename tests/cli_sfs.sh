#!/usr/bin/env bash
# frig sfs end to end on synthetic photos: frig synth -> detect -> fit -> sfs. A cloud per usable
# photo (WORKSPACE/clouds/STEM.ply), the albedo texture, a picture per judged photo, the sfs block
# in report.json, no cloud from a photo without a face or with a blown or dark exposure, the same
# files on a rerun, frig export taking the texture; and the errors: no workspace, no report.
set -u
. "$FRIG_SOURCE_DIR/tests/scripts/model_fixture.sh"
fail=0
check() { if ! eval "$1"; then echo "FAILED: $1"; fail=1; fi; }
F="$FRIG_CLI"
py=/usr/bin/python3
tmp="$FRIG_BINARY_DIR/test-tmp/cli_sfs"; rm -rf "$tmp"; mkdir -p "$tmp"
. "$FRIG_SOURCE_DIR/tests/scripts/scratch.sh"

check '"$F" help sfs | grep -q "usage: frig sfs -w WORKSPACE"'
"$F" sfs 2>/dev/null; check '[ $? = 2 ]'
"$F" --quiet sfs -w "$tmp/empty" 2>"$tmp/err"; check '[ $? = 1 ]'
check 'grep -q "no report.json yet" "$tmp/err"'

frig_test_model || frig_test_skip "no ICT-FaceKit data"
M="$FRIG_TEST_MODEL"
# 12 photos of one subject, 6 of them intended failures (occluder, extreme pose, no face,
# sunglasses, under- and over-exposed).
"$F" --quiet --set synth.image_size=320 --set synth.max_yaw=35 --set synth.failure_rate=0.5 --set synth.rig_obj=0 \
  synth --model "$M" -o "$tmp/synth" --photos 12 --seed 5 > /dev/null
check '[ $? = 0 ]'
"$F" --quiet detect "$tmp/synth/subject_00/photos" -w "$tmp/ws" --no-overlays && "$F" --quiet fit -w "$tmp/ws" --model "$M" --no-overlays
check '[ $? = 0 ]'
"$F" --quiet sfs -w "$tmp/ws" --model "$M"
check '[ $? = 0 ]'
summary=$($py - "$tmp/ws" "$tmp/synth/subject_00/truth" <<'PY'
import json, os, struct, sys
ws, truth = sys.argv[1], sys.argv[2]
r = json.load(open(os.path.join(ws, "report.json")))
judged = [p for p in r["photos"] if "sfs" in p]
clouds = 0
bad = 0
margins = 0
for p in judged:
    stem = os.path.splitext(os.path.basename(p["file"]))[0]
    ply = os.path.join(ws, "clouds", stem + ".ply")
    t = json.load(open(os.path.join(truth, stem + ".json")))
    has = os.path.exists(ply)
    if has != (p["status"] == "ok" and p["sfs"]["kept"] > 0):
        print("mismatch", stem); sys.exit(1)
    if has:
        clouds += 1
        head = open(ply, "rb").read(400).split(b"end_header\n")[0].decode()
        n = int([l for l in head.splitlines() if l.startswith("element vertex")][0].split()[2])
        if n != p["sfs"]["kept"] or "property float confidence" not in head:
            print("bad ply", stem); sys.exit(1)
        mply = os.path.join(ws, "clouds", "margin", stem + ".ply")  # the margin: neck, ears, scalp
        m = 0
        if os.path.exists(mply):
            mhead = open(mply, "rb").read(400).split(b"end_header\n")[0].decode()
            m = int([l for l in mhead.splitlines() if l.startswith("element vertex")][0].split()[2])
        if m != p["sfs"].get("margin", 0):
            print("bad margin", stem); sys.exit(1)
        margins += m > 0
        if t["failure"] in ("no_face", "underexposed", "overexposed"): bad += 1
    if len(p["sfs"]["lighting"]) != 3 or len(p["sfs"]["rotation"]) != 9:
        print("bad sfs block", stem); sys.exit(1)
png = open(os.path.join(ws, "textures", "albedo.png"), "rb").read(32)
w, h = struct.unpack(">II", png[16:24])
pics = len([f for f in os.listdir(os.path.join(ws, "overlays", "sfs")) if f.endswith(".jpg")])
print(len(judged), clouds, bad, w, h, pics, margins)
PY
)
echo "judged, clouds, clouds from failures, albedo size, pictures, clouds with a margin: $summary"
read njudged nclouds nbad tw th npics nmargins <<< "$summary"
# the albedo texture at sfs.texture_size 0: twice sfs.face_px (128) rounded up to a power of two
check '[ "$nclouds" -ge 4 ] && [ "$nbad" = 0 ] && [ "$tw" = 256 ] && [ "$th" = 256 ] && [ "$npics" = "$njudged" ]'
check '[ "$nmargins" -ge 1 ]'   # sfs.cloud_region 2: the neck, ears and scalp apart
# The shared solve moved the identity's modes, all 100 of them by default (sfs.identity_modes; at 40
# no more than 40 could move): report.json keeps what the clouds were drawn at (the fit's identity
# with that change), for retarget to start from.
idchange=$($py -c 'import json,sys; r=json.load(open(sys.argv[1])); a=r["fit"]["identity"]; b=r["sfs"]["identity"]; print(len(a) == len(b), sum(1 for x, y in zip(a, b) if x != y))' "$tmp/ws/report.json")
echo "sfs identity: as long as the fit's, weights changed: $idchange"
read idsame idmoved <<< "$idchange"
check '[ "$idsame" = True ] && [ "$idmoved" -ge 90 ] && [ "$idmoved" -le 100 ]'
# A rerun judges the same photos again and writes the same clouds.
mkdir -p "$tmp/first" && cp "$tmp/ws/clouds/"*.ply "$tmp/first/"
"$F" --quiet --threads 1 sfs -w "$tmp/ws" --no-overlays --model "$M"
check '[ $? = 0 ]'
for f in "$tmp/first/"*.ply; do check 'cmp -s "$f" "$tmp/ws/clouds/$(basename "$f")"'; done
# frig export takes the albedo as the face's texture.
"$F" --quiet export -w "$tmp/ws" -o "$tmp/rig.glb" > "$tmp/exp"
check '[ $? = 0 ] && grep -q "albedo.png" "$tmp/exp"'
exit $fail
