#!/usr/bin/env bash
# Reproduces the README's results tables: simulator suite (GMC on/off, dynamic-match
# precision/recall, ghost voxels, coverage) and the shared real data (GMC on/off and
# OpenCV's odometries on the same frames), plus per-stage timing. Writes Markdown to
# ${GMC_BENCH_DIR:-out/bench}/results.md. Real data from GMC_DATA_DIR (default
# ../shared/data); skipped with a message when absent.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/setup.sh"
"$root/scripts/build.sh" >/dev/null
bin="${GMC_BUILD_DIR:-$root/build}/bin"
out="${GMC_BENCH_DIR:-$root/out/bench}"
data="${GMC_DATA_DIR:-$root/../shared/data}"
frames="${GMC_BENCH_FRAMES:-300}"
mkdir -p "$out"
md="$out/results.md.tmp"

ate() { "$bin/gmc-eval" --gt "$1" --est "$2" | awk '/^ATE/ {print $3}'; }
json() { grep -o "\"$2\": [0-9.e+-]*" "$1" | head -1 | awk '{print $2}'; }
stage() { grep -o "\"$2\": {\"median\": [0-9.e+-]*, \"p95\": [0-9.e+-]*}" "$1" | awk -F'[:,} ]+' '{printf "%.2f (%.2f)", $3, $5}'; }

{
  echo "# GMC-RGBD results ($(date -u +%Y-%m-%d), $(nproc) cores)"
  echo
  echo "## Simulator ($frames frames each)"
  echo
  echo "| sequence | ATE with GMC (m) | ATE without GMC (m) | dyn. precision | dyn. recall | ghost voxels with / without GMC / GMC poses no mask | static coverage with / without GMC | odometry ms median (p95) |"
  echo "|---|---|---|---|---|---|---|---|"
} > "$md"
for s in walkers_xyz walkers_static walkers_halfsphere walkers_rpy; do
  seq="$out/sim/$s"
  echo "bench: $s" >&2
  "$bin/gmc-sim" "$root/config/sim/$s.ini" --out "$seq" --frames "$frames" >/dev/null
  for variant in on off nomask; do
    extra=()
    [ "$variant" = off ] && extra=(--set GMC.enabled=false)
    [ "$variant" = nomask ] && extra=(--set Mapping.use_dynamic_mask=false)
    "$bin/gmc-rgbd-mapping" "$root/config/default.ini" "$seq" --out "$out/run/$s-$variant" \
      --set Dataset.anchor_to_groundtruth=true --set Playback.progress=false "${extra[@]}" >/dev/null 2>&1
  done
  on="$out/run/$s-on/summary.json"; off="$out/run/$s-off/summary.json"; nm="$out/run/$s-nomask/summary.json"
  echo "| $s | $(ate "$seq/groundtruth.txt" "$out/run/$s-on/trajectory_tum.txt") | $(ate "$seq/groundtruth.txt" "$out/run/$s-off/trajectory_tum.txt") | $(json "$on" precision) | $(json "$on" recall) | $(json "$on" ghost_voxels) / $(json "$off" ghost_voxels) / $(json "$nm" ghost_voxels) | $(json "$on" static_coverage) / $(json "$off" static_coverage) | $(stage "$on" odometry) |" >> "$md"
done

if [ -d "$data/bonn_crowd_240_389" ] && [ -d "$data/tum_fr3_teddy_1_100" ]; then
  {
    echo
    echo "## Real data (ATE RMSE, m; same frames for every method)"
    echo
    echo "| sequence | GMC odometry | without GMC | OpenCV RgbdOdometry | OpenCV ICPOdometry | OpenCV RgbdICPOdometry | GMC odometry ms median (p95) | frontend | GMC | mapping | pipeline fps |"
    echo "|---|---|---|---|---|---|---|---|---|---|---|"
  } >> "$md"
  for pair in "bonn_crowd_240_389 bonn bonn" "tum_fr3_teddy_1_100 tum_fr3 fr3"; do
    set -- $pair
    echo "bench: $1" >&2
    d="$data/$1"
    "$bin/gmc-rgbd-mapping" "$root/config/$2.ini" "$d" --out "$out/run/$1-on" --set Playback.progress=false >/dev/null 2>&1
    "$bin/gmc-rgbd-mapping" "$root/config/$2.ini" "$d" --out "$out/run/$1-off" --set GMC.enabled=false --set Playback.progress=false >/dev/null 2>&1
    row="| $1 | $(ate "$d/groundtruth.txt" "$out/run/$1-on/trajectory_tum.txt") | $(ate "$d/groundtruth.txt" "$out/run/$1-off/trajectory_tum.txt")"
    for m in rgbd icp rgbd_icp; do
      "$bin/gmc-baseline-odometry" "$d" --camera "$3" --method $m --out "$out/run/$1-opencv-$m.txt" >/dev/null
      row="$row | $(ate "$d/groundtruth.txt" "$out/run/$1-opencv-$m.txt")"
    done
    s="$out/run/$1-on/summary.json"
    echo "$row | $(stage "$s" odometry) | $(stage "$s" frontend) | $(stage "$s" gmc) | $(stage "$s" mapping) | $(json "$s" fps) |" >> "$md"
  done
else
  echo -e "\nReal data not found in $data (set GMC_DATA_DIR): real-data rows skipped." >> "$md"
fi
mv "$md" "$out/results.md"
cat "$out/results.md"
