#!/usr/bin/env bash
# Install what libfrig needs on Debian 12, as root or through sudo.
#   scripts/install-deps.sh          build dependencies and the data files (dlib, OpenCV, face-api's
#                                    networks into /usr/local/share/frig/face-api/model)
#   scripts/install-deps.sh --test   also the reference tools the test suite compares against
#                                    (dlib, OpenCV's Python module, Blender, the glTF validator,
#                                    ffmpeg for video input, Chromium for the HTML report)
set -euo pipefail
SUDO=""
if [ "$(id -u)" != 0 ]; then SUDO="sudo"; fi

build_pkgs="build-essential cmake pkg-config libopenblas-dev liblapacke-dev libsuitesparse-dev
  libpng-dev libjpeg62-turbo-dev libcjson-dev zlib1g-dev libdlib-data opencv-data nodejs npm"
test_pkgs="ninja-build ccache libdlib-dev python3-opencv python3-numpy blender binutils abigail-tools ffmpeg chromium"

want="$build_pkgs"
if [ "${1:-}" = "--test" ]; then want="$want $test_pkgs"; fi

missing=""
for p in $want; do
  # A Node.js from elsewhere (e.g. NodeSource's, which bundles npm and conflicts with
  # Debian's npm package) serves as well as Debian's.
  case "$p" in nodejs) command -v node >/dev/null && continue ;; npm) command -v npm >/dev/null && continue ;; esac
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
if [ -n "$missing" ]; then
  echo "installing:$missing"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends $missing
fi

# npm prints its own reason (an unreachable registry, a proxy's certificate) on stderr; this
# says which download it was and where npm's settings are.
npm_failed() { # what
  echo "install-deps.sh: npm could not fetch $1 from $(npm config get registry 2>/dev/null || echo the npm registry)" \
       "(npm's error is above; behind a proxy, set npm's proxy and cafile: npm config set cafile FILE)." >&2
  exit 1
}

if [ "${1:-}" = "--test" ]; then
  # The Khronos glTF validator is an npm library; keep it in the build tree's tools folder.
  tools="$(cd "$(dirname "$0")/.." && pwd)/build/tools"
  if [ ! -f "$tools/node_modules/gltf-validator/package.json" ]; then
    mkdir -p "$tools"
    (cd "$tools" && npm install --loglevel=error --no-progress --no-audit --no-fund gltf-validator@2.0.0-dev.3.10 >/dev/null) ||
      npm_failed "gltf-validator@2.0.0-dev.3.10 (the glTF validator the tests run)"
  fi
fi

# The face networks (SSD MobileNet v1 detector, 68-point landmark net, face recognition net) of
# the npm package @vladmandic/face-api (MIT): only its model/ folder and licence are kept, in
# FRIG_FACE_MODELS_HOME (default /usr/local/share/frig/face-api), which is where libfrig looks
# by default (docs/identity.md). npm pack fetches the package's tarball without installing it.
faceapi_version=1.7.15
faceapi_home="${FRIG_FACE_MODELS_HOME:-/usr/local/share/frig/face-api}"
if [ ! -f "$faceapi_home/model/ssd_mobilenetv1_model-weights_manifest.json" ] ||
   [ "$(cat "$faceapi_home/VERSION" 2>/dev/null)" != "$faceapi_version" ]; then
  scratch="$(mktemp -d)"
  if ! (cd "$scratch" && npm pack --loglevel=error --no-progress "@vladmandic/face-api@$faceapi_version" >/dev/null &&
        tar -xzf vladmandic-face-api-"$faceapi_version".tgz package/model package/LICENSE); then
    rm -rf "$scratch"
    npm_failed "@vladmandic/face-api@$faceapi_version (the face networks)"
  fi
  $SUDO mkdir -p "$faceapi_home"
  $SUDO rm -rf "$faceapi_home/model"
  $SUDO cp -r "$scratch/package/model" "$scratch/package/LICENSE" "$faceapi_home/"
  echo "$faceapi_version" | $SUDO tee "$faceapi_home/VERSION" >/dev/null
  rm -rf "$scratch"
  echo "installed @vladmandic/face-api $faceapi_version's networks in $faceapi_home/model"
fi
