#!/usr/bin/env bash
# Installs voxlux's Debian 12 packages (when any is missing), builds it, and renders the bundled
# default scene to out/default.exr. Safe to run again: it only does what is not done yet.
set -euo pipefail
cd "$(dirname "$0")"

packages=(
  build-essential cmake ninja-build pkg-config
  ccache                      # rebuilds of unchanged files (and CI on a warm cache) are cache hits
  libopenvdb-dev libboost-iostreams-dev libopenvdb-tools
  libboost-dev                # Boost.Random's Sobol sequence (the reference's stratified numbers)
  libopenexr-dev openexr libtbb-dev libglm-dev nlohmann-json3-dev libcli11-dev
  libegl-dev libegl-mesa0 libgl1-mesa-dri libepoxy-dev
  libopencolorio-dev opencolorio-tools libpng-dev
  libnifti2-dev libdcmtk-dev  # voxlux import: NIfTI and DICOM scans (docs/scans.md)
  libassimp-dev               # camera.file and holdout meshes: OBJ, glTF and FBX (docs/compositing.md)
  libembree-dev               # holdout meshes: the camera's rays into them (docs/compositing.md)
  libgtest-dev
  libglfw3-dev libimgui-dev   # voxlux view: the window and its panels
  xvfb xdotool python3        # the viewer's tests: a virtual X display and real X events
  clang libclang-rt-14-dev   # the sanitizer build and its libFuzzer targets (tests/run.sh)
  slurm-wlm munge             # voxlux farm's test: a one-node Slurm cluster on localhost (docs/farm.md)
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${missing[@]}"
fi

cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build

mkdir -p out
build/voxlux render grids/default.json -o out/default.exr --preview out/default.png --stats out/default-stats.json
echo "setup: the default scene is in out/default.exr, with an sRGB preview in out/default.png (stage times above, and in out/default-stats.json)"
