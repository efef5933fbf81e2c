#!/usr/bin/env bash
# The retarget issue's table on frig synth subjects: for each subject of a synth set, its
# photos through detect -> filter -> fit, then clouds from the true depth (bench/truth_clouds:
# realistic = placed by the fitted pose, ideal = the true surface in the true head frame), then
# bench/retarget_eval (template, model-space fit, best in-span, each outer round).
# Usage: bench/retarget_sets.sh MODEL SYNTH_DIR OUT_DIR [ROUNDS] [-- retarget_eval options...]
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
build=${FRIG_BINARY_DIR:-$here/build}
model=$1 synth=$2 out=$3 rounds=${4:-3}
shift 3; [ $# -gt 0 ] && shift
[ "${1:-}" = "--" ] && shift
mkdir -p "$out"
for s in "$synth"/subject_*; do
  name=$(basename "$s")
  ws=$out/$name
  if [ ! -f "$ws/rig/rig.frigrig" ]; then
    rm -rf "$ws"
    "$build/frig" --quiet detect "$s"/photos/*.jpg -w "$ws"
    "$build/frig" --quiet filter -w "$ws"
    "$build/frig" --quiet fit -w "$ws" --model "$model" --no-overlays
  fi
  for kind in realistic ideal; do
    w=$out/${name}_$kind
    rm -rf "$w"; cp -r "$ws" "$w"
    if [ $kind = ideal ]; then "$build/bench/truth_clouds" "$w" --ideal >/dev/null; else "$build/bench/truth_clouds" "$w" >/dev/null; fi
    echo "### $name, clouds from the true depth ($kind)"
    "$build/bench/retarget_eval" "$model" "$w" --rounds "$rounds" "$@"
  done
done
