#!/usr/bin/env bash
# frig run on 100 photos: a real set and a frig synth subject. Prints per-stage seconds and
# peak memory (from each stage's record, OUT/stages/*/stage.json), the whole run's wall time and
# user + system CPU seconds (/usr/bin/time; on a machine shared with other jobs the wall time is
# inflated, the CPU seconds much less so), the ratio to the paper's ~3,000 s for 100 photos, and
# on the synthetic subject the personalized rig's neutral, E_B and delta errors against the true
# rig, with the fit's model-space rig (OUT/stages/fit/) and the mean face as baselines
# (bench/rig_error.c, bench/rig_score.h).
#   bench/pipeline.sh [build-dir] [work-dir] [real-set-folder] [threads]
# Defaults: build, build/bench-pipeline, ../shared/photos/video_sadtalker_WDA_KatieHill_000 (100
# frames of a real video), 2 threads.
# The peak memory is the largest stage's (VmHWM, reset per stage): frig run resets the kernel's
# high-water mark at each stage, so /usr/bin/time's maximum RSS is only the last stage's.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
work=${2:-$build/bench-pipeline}
shared="${FRIG_SHARED:-../shared}"
real=${3:-$shared/photos/video_sadtalker_WDA_KatieHill_000}
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
order = ["frames", "detect", "identity", "filter", "fit", "sfs", "retarget", "export", "report"]
recs = {}
for f in glob.glob(os.path.join(out, "stages", "*", "stage.json")):
    r = json.load(open(f))
    recs[r["stage"]] = r
rep = json.load(open(os.path.join(out, "report.json")))
n = len(rep["photos"])
used = sum(1 for p in rep["photos"] if p["status"] == "ok" and "fit" in p)
wall = cpu = None
for line in open(tlog):
    if line.startswith("WALL "): wall = float(line.split()[1])
    if line.startswith("CPU "): cpu = float(line.split()[1]) + float(line.split()[2])
print("\n== %s: %d photos in, %d used" % (name, n, used))
print("%-8s %9s %9s %10s  %s" % ("stage", "seconds", "CPU s", "peak MB", "result"))
total = total_cpu = 0.0
for s in order:
    if s in recs:
        r = recs[s]
        total += r["seconds"]
        total_cpu += r.get("cpu_seconds", 0)
        print("%-8s %9.2f %9.2f %10.0f  %s" % (s, r["seconds"], r.get("cpu_seconds", 0), r["peak_rss_mb"], r["summary"][:90]))
print("%-8s %9.2f %9.2f %10.0f  (sum of stages; the process: wall %.2f s, user + system CPU %.2f s)" % (
    "all", total, total_cpu, max(r["peak_rss_mb"] for r in recs.values()), wall, cpu))
print("paper: ~3000 s for 100 photos; this run %.1f s wall for %d photos = %.1f s per 100 photos: %.0fx faster"
      "%s; targets: under 60 s, under 2048 MB" % (
      wall, n, wall * 100 / n, 3000 / (wall * 100 / n),
      "" if "retarget" in recs else " (without sfs and retargeting)"))
rounds = rep.get("retarget", {}).get("rounds", [])
if rounds:
    print("retarget rounds: " + "; ".join("%.3f mm moved, %d photos, cloud RMS %.2f mm" % (
        q["change_mm"], q["photos"], q["rms_mm"]) for q in rounds))
PY
}

one() { # name, photos, out
  rm -rf "$3"
  /usr/bin/time -f "WALL %e
CPU %U %S" -o "$3.time" "$F" --threads "$threads" run "$2" -o "$3" --model "$model" > "$3.log" 2>&1
  report "$1" "$3" "$3.time"
}

one "real set $(basename "$real")" "$real" "$work/real"
one "synthetic subject (100 photos, seed 2027)" "$work/synth/subject_00/photos" "$work/synthetic"
echo
echo "the personalized rig (rig.glb), against the true rig; baselines below it:"
"$build/bench/rig_error" "$work/synthetic" "$work/synth/subject_00/rig/rig.frigrig" "$model"
# The fit's model-space rig, as a run folder of its own (rig/rig.frigrig and the fit's report).
fitdir="$work/synthetic-fit"
rm -rf "$fitdir" && mkdir -p "$fitdir/rig"
cp "$work/synthetic/stages/fit/rig.frigrig" "$fitdir/rig/" && cp "$work/synthetic/stages/fit/report.json" "$fitdir/"
echo
echo "the fit's model-space rig (before sfs and retarget), against the true rig:"
"$build/bench/rig_error" "$fitdir" "$work/synth/subject_00/rig/rig.frigrig" "$model"
