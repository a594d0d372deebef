#!/usr/bin/env bash
# CI: installs the build to a temporary prefix, builds a user's project against
# find_package(GmcRgbd) linking GmcRgbd::vo, and runs the installed gmc-rgbd-mapping on a
# generated sequence with its shipped configuration, from a folder with no source tree.
# usage: install_test.sh <build dir> <source dir>
set -euo pipefail
build="$1"
src="$2"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
prefix="$tmp/prefix"
cmake --install "$build" --prefix "$prefix" >/dev/null
for f in default bonn tum_fr3 sim/walkers_xyz; do
  test -f "$prefix/share/gmc-rgbd/config/$f.ini" || { echo "missing share/gmc-rgbd/config/$f.ini"; exit 1; }
done
cmake -S "$src/tests/install/consumer" -B "$tmp/consumer" -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$tmp/consumer" -j 2 >/dev/null
"$tmp/consumer/consumer"
cd "$tmp"
"$prefix/bin/gmc-sim" "$prefix/share/gmc-rgbd/config/sim/walkers_xyz.ini" --out "$tmp/seq" --frames 30 >/dev/null
"$prefix/bin/gmc-rgbd-mapping" "$tmp/seq" --out "$tmp/out" --set Playback.progress=false
test "$(grep -vc "^#" "$tmp/out/trajectory_tum.txt")" -eq 30
test -s "$tmp/out/map.bt"
printed="$("$prefix/bin/gmc-rgbd-mapping" --print-config --config default)"
grep -q "^chain = gmc" <<< "$printed"
"$prefix/bin/gmc-eval" --gt "$tmp/seq/groundtruth.txt" --est "$tmp/out/trajectory_tum.txt"
echo "install test: OK"
