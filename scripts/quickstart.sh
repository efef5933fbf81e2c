#!/usr/bin/env bash
# The first command of the README: install the dependencies, build, and run frig run on a
# sample set, printing where the report is. Install and build output go to quickstart.log.
#   scripts/quickstart.sh [PHOTOS_OR_VIDEO...]
# The face model: $FRIG_MODEL or ~/.local/share/frig/ict.frigmodel when imported already, else
# imported from ICT-FaceKit at $FRIG_ICT (default ../shared/ict-facekit). The photos: the
# arguments, else ../shared/photos/lfw_tony_blair, else 40 photos of a subject made by frig synth.
set -euo pipefail
cd "$(dirname "$0")/.."
log="$PWD/quickstart.log"
shared="${FRIG_SHARED:-../shared}"
ict="${FRIG_ICT:-$shared/ict-facekit}"
model="${FRIG_MODEL:-${XDG_DATA_HOME:-$HOME/.local/share}/frig/ict.frigmodel}"

if [ ! -f "$model" ] && [ ! -f "$ict/generic_neutral_mesh.obj" ]; then
  echo "libfrig needs the ICT-FaceKit head model (MIT), which is not here: git clone" \
       "https://github.com/ICT-VGL/ICT-FaceKit and run FRIG_ICT=\$PWD/ICT-FaceKit/FaceXModel $0 (it imports it once)."
  exit 1
fi

: > "$log"
step() { # what, command...
  local what=$1; shift
  printf '%s ... ' "$what"
  local t0=$SECONDS
  if "$@" >> "$log" 2>&1; then echo "done ($((SECONDS - t0)) s)"; else
    echo "failed; the last lines of $log:"; tail -n 15 "$log"; exit 1; fi
}
step "installing the Debian packages (scripts/install-deps.sh)" scripts/install-deps.sh
step "configuring" cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo
step "building" cmake --build build -j "$(nproc)"
F=build/frig
if [ ! -f "$model" ]; then
  step "importing ICT-FaceKit from $ict into $model" "$F" model import-ict "$ict" -o "$model"
fi
export FRIG_MODEL="$model"

if [ $# -gt 0 ]; then
  photos=("$@")
elif [ -d "$shared/photos/lfw_tony_blair" ]; then
  photos=("$shared/photos/lfw_tony_blair")
else
  echo "no photos given and no $shared/photos: making a synthetic subject to run on (frig synth)"
  step "rendering 40 photos of a synthetic subject into out/synth" "$F" --set synth.rig_obj=0 synth -o out/synth --photos 40
  photos=(out/synth/subject_00/photos)
fi
echo "frig run ${photos[*]} -o out"
"$F" run "${photos[@]}" -o out
