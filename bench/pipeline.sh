#!/usr/bin/env bash
# frig run on 100 photos: a real set and a frig synth subject. Prints per-stage seconds and
# peak memory (from each stage's record, OUT/stages/*/stage.json), the whole run's wall time
# and peak RSS (/usr/bin/time), the ratio to the paper's ~3,000 s for 100 photos, and on the
# synthetic subject the rig's neutral, E_B and delta errors against the true rig, with the
# model-space rig and the mean face as baselines (bench/rig_error.c).
#   bench/pipeline.sh [build-dir] [work-dir] [real-set-folder] [threads]
# Defaults: build, build/bench-pipeline, ../shared/photos/bing_will_smith, 2 threads.
# Times depend on the machine's load: run it on a quiet machine (nice it next to others).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
work=${2:-$build/bench-pipeline}
shared="${FRIG_SHARED:-../shared}"
real=${3:-$shared/photos/bing_will_smith}
threads=${4:-2}
F="$build/frig"
model="$work/ict.frigmodel"
mkdir -p "$work"
[ -f "$model" ] || "$F" --quiet model import-ict "$shared/ict-facekit" -o "$model" > /dev/null
if [ ! -f "$work/synth/index.json" ]; then
  "$F" --quiet --threads "$threads" --set synth.rig_obj=0 synth --model "$model" -o "$work/synth" --photos 100 --seed 2027 > /dev/null
fi

report() { # name, run folder, /usr/bin/time log
  /usr/bin/python3 - "$1" "$2" "$3" <<'PY'
import glob, json, os, sys
name, out, tlog = sys.argv[1:4]
order = ["frames", "detect", "identity", "filter", "fit", "export", "report"]
recs = {}
for f in glob.glob(os.path.join(out, "stages", "*", "stage.json")):
    r = json.load(open(f))
    recs[r["stage"]] = r
rep = json.load(open(os.path.join(out, "report.json")))
n = len(rep["photos"])
used = sum(1 for p in rep["photos"] if p["status"] == "ok" and "fit" in p)
wall = rss = None
for line in open(tlog):
    if line.startswith("WALL "): wall = float(line.split()[1])
    if line.startswith("RSS "): rss = float(line.split()[1]) / 1024
print("\n== %s: %d photos in, %d used" % (name, n, used))
print("%-8s %9s %10s  %s" % ("stage", "seconds", "peak MB", "result"))
total = 0.0
for s in order:
    if s in recs:
        r = recs[s]
        total += r["seconds"]
        print("%-8s %9.2f %10.0f  %s" % (s, r["seconds"], r["peak_rss_mb"], r["summary"][:90]))
print("%-8s %9.2f %10.0f  (sum of stages; wall %.2f s, peak RSS of the process %.0f MB)" % (
    "all", total, max(r["peak_rss_mb"] for r in recs.values()), wall, rss))
print("paper: ~3000 s for 100 photos; this run %.1f s for %d photos = %.1f s per 100 photos: %.0fx faster"
      " (the paper's figure includes sfs and retargeting, which frig run does not run yet)" % (
      wall, n, wall * 100 / n, 3000 / (wall * 100 / n)))
PY
}

one() { # name, photos, out
  rm -rf "$3"
  /usr/bin/time -f "WALL %e
RSS %M" -o "$3.time" "$F" --threads "$threads" run "$2" -o "$3" --model "$model" > "$3.log" 2>&1
  report "$1" "$3" "$3.time"
}

one "real set $(basename "$real")" "$real" "$work/real"
one "synthetic subject (100 photos, seed 2027)" "$work/synth/subject_00/photos" "$work/synthetic"
echo
"$build/bench/rig_error" "$work/synthetic" "$work/synth/subject_00/rig/rig.frigrig" "$model"
