#!/usr/bin/env bash
# Detect, filter and fit on every photo set in ../shared/photos, one workspace per set, and
# print a table: photos, statuses after each stage, landmark fit error (median RMS over the fitted
# photos, in pixels and in % of the eye distance), and per-stage times.
# Usage: bench/pipeline_sets.sh [build-dir] [work-dir] [model]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
work=${2:-$build/pipeline-sets}
model=${3:-}
shared="${FRIG_SHARED:-../shared}"
F="$build/frig"
margs=()
[ -n "$model" ] && margs=(--model "$model")
mkdir -p "$work"
printf "%-36s %6s %6s %8s %8s %6s %6s %8s %7s %9s %8s %7s %7s %7s\n" set photos ok no_face unread dup outlier fitted fitfail \
  "err px" "err %eye" detect filter fit
for dir in "$shared"/photos/*/; do
  name=$(basename "$dir")
  ws="$work/$name"
  rm -rf "$ws"
  t0=$(date +%s.%N)
  "$F" --quiet detect "$dir" -w "$ws" >/dev/null
  t1=$(date +%s.%N)
  "$F" --quiet filter -w "$ws" >/dev/null
  t2=$(date +%s.%N)
  "$F" --quiet fit -w "$ws" "${margs[@]}" --no-overlays >/dev/null 2>&1 || true
  t3=$(date +%s.%N)
  /usr/bin/python3 - "$ws/report.json" "$name" "$t0" "$t1" "$t2" "$t3" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
ph = r["photos"]
count = lambda s: sum(1 for p in ph if p["status"] == s)
fitted = [p for p in ph if "fit" in p]
errs = sorted(p["fit"]["reprojection_error_px"] for p in fitted)
med = errs[len(errs) // 2] if errs else float("nan")
def eye_pct(p):
    q = p["faces"][p["subject"]]["landmarks"]
    l = [sum(q[k][d] for k in range(36, 42)) / 6 for d in (0, 1)]
    r = [sum(q[k][d] for k in range(42, 48)) / 6 for d in (0, 1)]
    return 100 * p["fit"]["reprojection_error_px"] / ((l[0] - r[0]) ** 2 + (l[1] - r[1]) ** 2) ** 0.5
rel = sorted(eye_pct(p) for p in fitted)
med_rel = rel[len(rel) // 2] if rel else float("nan")
t0, t1, t2, t3 = map(float, sys.argv[3:7])
print("%-36s %6d %6d %8d %8d %6d %6d %8d %7d %9.2f %8.2f %6.1fs %6.1fs %6.1fs" % (sys.argv[2], len(ph), count("ok"),
      count("no_face") + count("face_too_small"), count("unreadable"), count("duplicate"), count("outlier"), len(fitted),
      count("fit_failed"), med, med_rel, t1 - t0, t2 - t1, t3 - t2))
PY
done
