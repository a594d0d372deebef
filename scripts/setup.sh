#!/usr/bin/env bash
# Installs the Debian packages GMC-RGBD needs, non-interactively; does nothing when
# they are all present. Narrow MRPT set on purpose: libmrpt-dev drags in ROS and wx.
set -euo pipefail
packages=(
  build-essential cmake pkg-config ccache python3   # python3: the evaluation scripts and their test
  libeigen3-dev libopencv-dev libopencv-contrib-dev liboctomap-dev
  libmrpt-config-dev libmrpt-obs-dev libmrpt-opengl-dev
  libtclap-dev nlohmann-json3-dev   # argument parsing, JSON (header-only)
  libgtest-dev libbenchmark-dev
  mrpt-common   # /usr/share/mrpt/datasets/tests_rgbd.rawlog, read by the tests
  mrpt-apps     # rawlog-edit, used to check that MRPT reads our rawlogs
)
missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
echo "setup: installing ${missing[*]}"
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "setup: done"
