#!/usr/bin/env bash
# The identity step on sets built from ../shared/photos (bench/identity_eval.c): a person's photos
# with 5-20% photos of other people planted and 8 composites of the person beside a larger
# stranger; precision / recall of other_person, own photos kept and composites right, for each
# identity.threshold, and for SSD score thresholds given as arguments (default: 0.5 0.3 0.2).
#   bench/identity_sets.sh [MIN_SCORE...]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${FRIG_BUILD_DIR:-$PWD/build}
p=${FRIG_SHARED:-$PWD/../shared}/photos
cmake --build "$build" -j2 --target bench_identity_eval >/dev/null
scores=("$@")
[ ${#scores[@]} -gt 0 ] || scores=(0.5 0.3 0.2)
for s in "${scores[@]}"; do
  echo "=== detect.ssd_min_score = $s"
  run() { "$build/bench/identity_eval" --set detect.ssd_min_score="$s" "$@"; echo; }
  run --planted 0.10 "$p/lfw_george_w_bush" "$p/lfw_colin_powell" "$p/lfw_tony_blair" "$p/bing_will_smith"
  run --planted 0.20 "$p/lfw_tony_blair" "$p/lfw_george_w_bush" "$p/lfw_colin_powell" "$p/video_liveportrait_d6"
  run --planted 0.05 "$p/video_sadtalker_WDA_KatieHill_000" "$p/lfw_colin_powell" "$p/bing_mel_gibson"
  run --planted 0.15 "$p/lfw_colin_powell" "$p/lfw_tony_blair" "$p/bing_mel_gibson" "$p/outliers"
done
