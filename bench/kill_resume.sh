#!/usr/bin/env bash
# frig run killed (SIGKILL) at K random points and resumed until it finishes, against a clean
# run: rig.glb, shapes/ and clouds/ must be the same bytes. Each kill comes after a random share
# (5-70%) of the work the clean run's stage times say is left (less than that is left when detect
# resumes from its last batch). Prints where each kill landed.
#   bench/kill_resume.sh INPUT [work-dir] [kills] [seed] [-- extra frig options]
# e.g. bench/kill_resume.sh ../shared/photos/video_liveportrait_d6/source_video.mp4 /tmp/kr 5
# The command is $FRIG_CLI when set (tests/cli_run.sh runs this as its kill test), else build/frig.
set -euo pipefail
input=$(realpath "$1")
work=${2:-build/kill-resume}
mkdir -p "$work"
work=$(realpath "$work")
kills_wanted=${3:-5}
RANDOM=${4:-2026}
shift $(($# < 4 ? $# : 4))
[ "${1:-}" = "--" ] && shift
cd "$(dirname "$0")/.."
F=${FRIG_CLI:-build/frig}
rm -rf "$work/clean" "$work/killed"
t0=$SECONDS
"$F" --threads 2 run "$input" -o "$work/clean" --no-report "$@" > "$work/clean.log" 2>&1
echo "clean run: $((SECONDS - t0)) s"
left() { /usr/bin/python3 - "$work/clean" "$work/killed" <<'PY'
import glob, json, os, sys
ref, run = sys.argv[1:3]
t = 0.0
for f in glob.glob(os.path.join(ref, "stages", "*", "stage.json")):
    r = json.load(open(f))
    if not os.path.exists(os.path.join(run, "stages", r["stage"], "stage.json")): t += r["seconds"]
print("%.3f" % t)
PY
}
kills=0 misses=0 scale=1
while [ $kills -lt "$kills_wanted" ]; do
  work_left=$(left)
  delay=$(awk -v r=$RANDOM -v t="$work_left" -v k=$scale 'BEGIN{printf "%.3f", k * (0.05 + 0.65 * r / 32767.0) * t}')
  "$F" --threads 2 run "$input" -o "$work/killed" --no-report "$@" > "$work/killed.$kills.log" 2>&1 &
  pid=$!
  sleep "$delay"
  if kill -9 $pid 2>/dev/null; then
    kills=$((kills + 1))
    stage=$(grep -o "\[[0-9]/[0-9]\] [a-z]*" "$work/killed.$((kills - 1)).log" | tail -1)
    echo "kill $kills after $delay s of a resumed run (${work_left} s of work left), during $stage"
  fi
  wait $pid 2>/dev/null || true
  if [ "$(left)" = "0.000" ]; then
    # the run finished before its kill (the machine ran faster than during the clean run): with no
    # kill yet, start over with shorter delays (at most 4 times)
    [ $kills -gt 0 ] || [ $misses -ge 4 ] && break
    misses=$((misses + 1)) scale=$(awk -v k=$scale 'BEGIN{print k / 2}')
    echo "the run finished before its kill ($delay s): again from the start with delays times $scale"
    rm -rf "$work/killed"
  fi
done
"$F" --threads 2 run "$input" -o "$work/killed" --no-report "$@" > "$work/final.log" 2>&1
same=1
cmp -s "$work/clean/rig.glb" "$work/killed/rig.glb" || same=0
diff -rq "$work/clean/shapes" "$work/killed/shapes" > /dev/null || same=0
if [ -d "$work/clean/clouds" ] || [ -d "$work/killed/clouds" ]; then diff -rq "$work/clean/clouds" "$work/killed/clouds" > /dev/null || same=0; fi
echo "$kills kills; rig.glb, shapes/ and clouds/ $([ $same = 1 ] && echo "byte-identical to the clean run" || echo "DIFFER from the clean run")"
[ $same = 1 ]
