#!/usr/bin/env bash
# Installs the Debian packages libpyramid builds and tests with (needs root or sudo).
set -euo pipefail
packages=(
  build-essential cmake ninja-build lld pkg-config git
  libtiff-dev libdeflate-dev libpng-dev libjpeg-dev zlib1g-dev libopenimageio-dev libopenexr-dev libsquish-dev libstb-dev libgeographiclib-dev libgeotiff-dev
  libcli11-dev nlohmann-json3-dev libgtest-dev
  libcpp-httplib-dev libjs-three
  libegl-dev libgl-dev libgl1-mesa-dri libegl-mesa0
  openimageio-tools help2man python3
  python3-numpy python3-pytest python3-pip python3-setuptools python3-wheel chromium
  openmpi-bin libopenmpi-dev openssh-client
)
# The fuzz targets (fuzz/README.md) build with clang, whose OpenMP needs libomp.
if [ "${PYRAMID_BUILD_FUZZERS:-OFF}" = ON ]; then
  packages+=(clang libclang-rt-14-dev libomp-dev)
fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
echo "installing: ${missing[*]}" >&2
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
