#!/usr/bin/env bash
# frig detect on a temporary folder: a few shared photos, an upper-case extension, a cut JPEG,
# a 0-byte file, a photo without a face, a tiny face, a photo with user landmarks (.pts) and a
# text file that is not a photo. Statuses in report.json, landmarks, overlays, exit codes, a
# rerun replacing the report, a missing data file naming its package, the progress bar.
set -u
fail=0
check() { if ! eval "$1"; then echo "FAILED: $1"; fail=1; fi; }
F="$FRIG_CLI"
shared="${FRIG_SHARED:-$FRIG_SOURCE_DIR/../shared}"
skip() {
  echo "SKIPPED: $1" >&2
  if [ -n "${FRIG_REQUIRE_DATA:-}" ]; then exit 1; fi
  exit 77
}
[ -d "$shared/photos" ] || skip "no ../shared/photos"
[ -f /usr/share/dlib/shape_predictor_68_face_landmarks.dat ] || skip "libdlib-data is not installed"
[ -f /usr/share/opencv4/haarcascades/haarcascade_frontalface_alt2.xml ] || skip "opencv-data is not installed"
/usr/bin/python3 -c 'import cv2' 2>/dev/null || skip "python3-opencv is not installed (makes the tiny-face photo)"

tmp="$FRIG_BINARY_DIR/test-tmp/cli_detect"; rm -rf "$tmp"; mkdir -p "$tmp/in"
. "$FRIG_SOURCE_DIR/tests/scripts/scratch.sh"
in=$tmp/in
cp "$shared/photos/lfw_tony_blair/Tony_Blair_0001.jpg" "$in/a_blair.jpg"
cp "$shared/photos/lfw_colin_powell/Colin_Powell_0001.jpg" "$in/b_powell.JPG"
cp "$shared/photos/video_liveportrait_d6/frame_0001.jpg" "$in/c_frame.jpeg"
head -c 3000 "$shared/photos/lfw_tony_blair/Tony_Blair_0002.jpg" > "$in/d_cut.jpg"
: > "$in/e_empty.jpg"
cp "$shared/photos/outliers/nonface_rocket_skimage.jpg" "$in/f_rocket.jpg"
cp "$shared/photos/landmarks_300w_lfpw/lfpw_trainset_image_0001.png" "$in/g_user.png"
cp "$shared/photos/landmarks_300w_lfpw/lfpw_trainset_image_0001.pts" "$in/g_user.pts"
echo "not a photo" > "$in/notes.txt"
ln -s "$tmp/nowhere.jpg" "$in/i_gone.jpg"   # a broken link is reported, not skipped
mkdir "$in/sub" && cp "$in/a_blair.jpg" "$in/sub/"   # folders are not searched recursively
# A tiny face: an LFW photo shrunk from 150 to 72 px (face ~29 px, eyes ~13 px apart) in a gray 120 px frame.
/usr/bin/python3 - "$in/a_blair.jpg" "$in/h_tiny.png" <<'PY'
import sys, cv2, numpy as np
img = cv2.imread(sys.argv[1])
small = cv2.resize(img, (72, 72), interpolation=cv2.INTER_LINEAR_EXACT)
out = np.full((120, 120, 3), 128, np.uint8)
out[20:92, 20:92] = small
cv2.imwrite(sys.argv[2], out)
PY

ws=$tmp/ws
"$F" --set detect.detector=1 --set detect.descriptors=0 detect "$in" -w "$ws" > "$tmp/out" 2> "$tmp/err"; rc=$?
check '[ $rc = 0 ]'
cat "$tmp/err"
check 'grep -q "^9 photos, " "$tmp/out"'
check '[ -f "$ws/report.json" ]'
/usr/bin/python3 - "$ws/report.json" "$in/g_user.pts" > "$tmp/check" 2>&1 <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
photos = {p["file"].rsplit("/", 1)[-1]: p for p in r["photos"]}
want = {"a_blair.jpg": "ok", "b_powell.JPG": "ok", "c_frame.jpeg": "ok", "d_cut.jpg": "unreadable",
        "e_empty.jpg": "unreadable", "f_rocket.jpg": "no_face", "g_user.png": "ok", "h_tiny.png": "face_too_small",
        "i_gone.jpg": "unreadable"}
bad = []
if [p["file"].rsplit("/", 1)[-1] for p in r["photos"]] != sorted(want):
    bad.append("photos or order: %s" % list(photos))
for name, status in want.items():
    p = photos.get(name)
    if p is None or p["status"] != status:
        bad.append("%s: %s, want %s" % (name, p and p["status"], status))
        continue
    if status in ("unreadable", "no_face", "face_too_small") and not p.get("reason"):
        bad.append(name + ": no reason")
    for f in p["faces"]:
        if len(f["landmarks"]) != 68 or len(f["box"]) != 4:
            bad.append(name + ": face without 68 landmarks and a box")
    if status == "ok" and not (0 <= p["subject"] < len(p["faces"])):
        bad.append(name + ": subject %d of %d faces" % (p["subject"], len(p["faces"])))
    if status in ("unreadable", "no_face") and (p["faces"] or p["subject"] != -1):
        bad.append(name + ": faces on a failed photo")
if "no such file" not in photos["i_gone.jpg"].get("reason", "") or not photos["i_gone.jpg"]["file"].startswith("/"):
    bad.append("i_gone.jpg: %r, reason %r" % (photos["i_gone.jpg"]["file"], photos["i_gone.jpg"].get("reason")))
if "empty" not in photos["e_empty.jpg"].get("reason", ""):
    bad.append("e_empty.jpg: reason %r" % photos["e_empty.jpg"].get("reason"))
if photos["a_blair.jpg"]["width"] != 150 or photos["c_frame.jpeg"]["width"] != 480:
    bad.append("photo sizes")
# User landmarks: the .pts points shifted to 0-based, source "user", box = their bounding box.
lines = open(sys.argv[2]).read().split("{")[1].split("}")[0].split("\n")
pts = [[float(v) - 1 for v in l.split()] for l in lines if l.strip()]
u = photos["g_user.png"]["faces"]
if len(u) != 1 or u[0]["source"] != "user":
    bad.append("g_user.png: want one user face")
else:
    err = max(abs(a - b) for p, q in zip(u[0]["landmarks"], pts) for a, b in zip(p, q))
    if err > 1e-9:
        bad.append("g_user.png: landmarks differ from the .pts by %g" % err)
    xs = [p[0] for p in pts]
    if abs(u[0]["box"][0] - min(xs)) > 1e-9 or abs(u[0]["box"][2] - (max(xs) - min(xs))) > 1e-9:
        bad.append("g_user.png: box is not the landmarks' bounding box")
# Detected faces: landmarks inside the photo and near their box.
for name in ("a_blair.jpg", "b_powell.JPG", "c_frame.jpeg"):
    p = photos[name]
    f = p["faces"][p["subject"]]
    x, y, w, h = f["box"]
    inside = sum(x - 0.2 * w <= a <= x + 1.2 * w and y - 0.2 * h <= b <= y + 1.2 * h for a, b in f["landmarks"])
    if inside < 68 or f["source"] != "frontal":
        bad.append("%s: %d of 68 landmarks near the box, source %s" % (name, inside, f["source"]))
print("\n".join(bad) if bad else "report ok")
PY
cat "$tmp/check"
check 'grep -qx "report ok" "$tmp/check"'
check '[ $(ls "$ws/overlays/detect" | wc -l) = 9 ]'
check '[ -s "$ws/overlays/detect/3_d_cut.jpg" ] && [ -s "$ws/overlays/detect/7_h_tiny.jpg" ]'
check '"$F" info "$ws/overlays/detect/0_a_blair.jpg" | grep -q "150x150"'

# A folder with no photos: a sentence naming what it looked for, exit 1, no workspace written.
mkdir "$tmp/none" && echo "not a photo" > "$tmp/none/notes.txt"
"$F" detect "$tmp/none" -w "$tmp/ws_none" 2> "$tmp/err_none"; rc=$?
check '[ $rc = 1 ]'
check 'grep -q "none: the folder has no photos (.jpg, .jpeg, .png)" "$tmp/err_none"'
check '[ ! -e "$tmp/ws_none/report.json" ]'

# A new run replaces the report and the overlays; detect.user_landmarks=0 ignores the .pts.
"$F" --quiet --set detect.detector=1 --set detect.descriptors=0 detect "$in/g_user.png" -w "$ws" --set detect.user_landmarks=0 > "$tmp/out2"; rc=$?
check '[ $rc = 0 ]'
check '[ ! -s "$tmp/out2" ]'
check '/usr/bin/python3 -c "import json,sys; r=json.load(open(sys.argv[1])); p=r[\"photos\"]; sys.exit(not (len(p)==1 and p[0][\"status\"]==\"ok\" and p[0][\"faces\"][p[0][\"subject\"]][\"source\"]==\"frontal\"))" "$ws/report.json"'
check '[ $(ls "$ws/overlays/detect" | wc -l) = 1 ]'
"$F" --set detect.detector=1 --set detect.descriptors=0 detect "$in/a_blair.jpg" -w "$ws" --no-overlays > /dev/null; check '[ $? = 0 ]'
check '[ $(ls "$ws/overlays/detect" | wc -l) = 1 ]'

# Usage errors and a missing data file.
"$F" --set detect.detector=1 --set detect.descriptors=0 detect "$in/a_blair.jpg" 2> "$tmp/err"; check '[ $? = 2 ]'
check 'grep -q "no workspace" "$tmp/err"'
"$F" --set detect.detector=1 --set detect.descriptors=0 detect -w "$ws" 2> /dev/null; check '[ $? = 2 ]'
"$F" --set detect.detector=1 --set detect.descriptors=0 detect "$in/notes.txt" -w "$tmp/ws3" > /dev/null; check '[ $? = 0 ]'   # named directly: tried, unreadable
"$F" --set detect.detector=1 --set detect.descriptors=0 detect "$in/a_blair.jpg" "$in/no_such.jpg" -w "$tmp/ws6" 2> "$tmp/err"; check '[ $? = 1 ]'  # missing: an error
check 'grep -q "no_such.jpg: no such file or folder" "$tmp/err" && [ ! -e "$tmp/ws6/report.json" ]'
: > "$tmp/clip.mp4"
"$F" --set detect.detector=1 --set detect.descriptors=0 detect "$tmp/clip.mp4" -w "$tmp/ws6" 2> "$tmp/err"; check '[ $? = 1 ]'
check 'grep -q "clip.mp4 is a video: frig run samples frames" "$tmp/err"'
check 'grep -q "\"unreadable\"" "$tmp/ws3/report.json"'
"$F" --set detect.detector=1 --set detect.descriptors=0 detect "$in/a_blair.jpg" -w "$tmp/ws2" --cascades "$tmp/nowhere" 2> "$tmp/err"; check '[ $? = 1 ]'
check 'grep -q "opencv-data" "$tmp/err"'
"$F" --set detect.detector=1 --set detect.descriptors=0 detect "$in/a_blair.jpg" -w "$tmp/ws2" --landmark-model "$tmp/nowhere.dat" 2> "$tmp/err"; check '[ $? = 1 ]'
check 'grep -q "libdlib-data" "$tmp/err"'

# Byte-identical copies (scraped sets repeat photos): the later copy is a duplicate naming the first.
mkdir -p "$tmp/dup" && cp "$in/a_blair.jpg" "$tmp/dup/x.jpg" && cp "$in/a_blair.jpg" "$tmp/dup/y.jpg"
cp "$in/b_powell.JPG" "$tmp/dup/z.jpg"
"$F" --quiet --set detect.detector=1 --set detect.descriptors=0 detect "$tmp/dup" -w "$tmp/ws5" --no-overlays; check '[ $? = 0 ]'
dupcheck='import json,sys; p={q["file"].rsplit("/",1)[-1]: q for q in json.load(open(sys.argv[1]))["photos"]}
sys.exit(not (p["x.jpg"]["status"]=="ok" and p["z.jpg"]["status"]==sys.argv[2] and p["y.jpg"]["status"]==sys.argv[3]
              and (sys.argv[3]=="ok" or p["y.jpg"]["reason"].endswith("x.jpg"))))'
check '/usr/bin/python3 -c "$dupcheck" "$tmp/ws5/report.json" ok duplicate'
"$F" --quiet --set detect.duplicates=0 --set detect.detector=1 --set detect.descriptors=0 detect "$tmp/dup" -w "$tmp/ws5" --no-overlays; check '[ $? = 0 ]'
check '/usr/bin/python3 -c "$dupcheck" "$tmp/ws5/report.json" ok ok'

# The progress bar, on a terminal.
if command -v script > /dev/null; then
  script -qec "'$F' detect '$in' -w '$tmp/ws4' --no-overlays" /dev/null > "$tmp/tty" 2>&1
  check 'grep -q "detect .*\[#*\] 9/9" "$tmp/tty"'
fi
exit $fail
