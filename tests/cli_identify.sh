#!/usr/bin/env bash
# frig detect's identity step and frig identify on real photos with face-api's networks: four
# photos of one person and one of another; the other is other_person with its distance, the
# report holds descriptors and the set's identity, a rerun with a loose threshold gives the
# photo back, two people equally often stop with a sentence (exit 1, detections kept), and the
# usage errors.
set -u
fail=0
check() { if ! eval "$1"; then echo "FAILED: $1"; fail=1; fi; }
F="$FRIG_CLI"
py=/usr/bin/python3
tmp="$FRIG_BINARY_DIR/test-tmp/cli_identify"; rm -rf "$tmp"; mkdir -p "$tmp/photos" "$tmp/two"
. "$FRIG_SOURCE_DIR/tests/scripts/scratch.sh"
shared="${FRIG_SHARED:-$FRIG_SOURCE_DIR/../shared}"
models="${FRIG_FACE_MODELS:-/usr/local/share/frig/face-api/model}"

check '"$F" help identify | grep -q "usage: frig identify -w WORKSPACE"'
"$F" identify 2>/dev/null; check '[ $? = 2 ]'
"$F" identify -w "$tmp/none" 2>"$tmp/err"; check '[ $? = 1 ]'

blair="$shared/photos/lfw_tony_blair"
bush="$shared/photos/lfw_george_w_bush"
if [ ! -d "$blair" ] || [ ! -f "$models/ssd_mobilenetv1_model-weights_manifest.json" ]; then
  echo "*** SKIPPED: shared photos or face-api's networks ($models) missing ***"
  [ -n "${FRIG_REQUIRE_DATA:-}" ] && exit 1
  exit 77
fi
for f in 0001 0025 0049 0123; do ln -s "$blair/Tony_Blair_$f.jpg" "$tmp/photos/"; done
ln -s "$bush/George_W_Bush_0001.jpg" "$tmp/photos/"
"$F" detect "$tmp/photos" -w "$tmp/ws" > "$tmp/out"; check '[ $? = 0 ]'
check 'grep -q "identity: 5 photos judged, 1 of other people" "$tmp/out"'
check 'grep -q "other_person 1" "$tmp/out"'
check '$py -c "
import json, sys
r = json.load(open(sys.argv[1]))
p = {x[\"file\"].split(\"/\")[-1]: x for x in r[\"photos\"]}
b = p[\"George_W_Bush_0001.jpg\"]
assert b[\"status\"] == \"other_person\" and \"identity.threshold\" in b[\"reason\"], b[\"status\"]
assert all(len(f[\"descriptor\"]) == 128 and \"identity_distance\" in f for x in r[\"photos\"] for f in x[\"faces\"])
assert r[\"identity\"][\"photos\"] == 4 and len(r[\"identity\"][\"descriptor\"]) == 128
assert all(x[\"faces\"][x[\"subject\"]][\"source\"] == \"ssd\" for x in r[\"photos\"])
" "$tmp/ws/report.json"'
"$F" --quiet --set identity.threshold=1.5 identify -w "$tmp/ws"; check '[ $? = 0 ]'
check '! grep -q "\"status\": \"other_person\"" "$tmp/ws/report.json"'
"$F" identify -w "$tmp/ws" > "$tmp/out2"; check '[ $? = 0 ]'
check 'grep -q "1 of other people" "$tmp/out2"'
# two people, two photos each: no dominant identity; the detections are saved, the exit is 1
for f in 0001 0025; do ln -s "$blair/Tony_Blair_$f.jpg" "$tmp/two/"; done
for f in 0001 0006; do ln -s "$bush/George_W_Bush_$f.jpg" "$tmp/two/"; done
"$F" detect "$tmp/two" -w "$tmp/ws2" > /dev/null 2> "$tmp/err2"; check '[ $? = 1 ]'
check 'grep -q "no dominant identity" "$tmp/err2"'
check '[ -f "$tmp/ws2/report.json" ]'
"$F" --quiet --set identity.min_dominance=1 identify -w "$tmp/ws2"; check '[ $? = 0 ]'
exit $fail
