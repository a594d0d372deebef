#!/usr/bin/env bash
# Regenerates doc/sim.md's calibration table: the same per-frame statistics of the
# odometry's matches (bench/calibration_stats.cpp) on the two shared Bonn crowd windows
# and on config/sim/crowd.ini, stop_and_go.ini and stop_and_go_hover.ini, and each sequence's ATE with GMC off.
#
#   ./scripts/calibrate_sim.sh [SEED...]      # seeds of each scenario, default: 1 2
#   GMC_CALIB_SCENARIOS="crowd stop_and_go stop_and_go_hover"    # config/sim/<name>.ini scenarios (this default)
#
# Sim sequences have 150 frames, like the real windows (150 and 160). Output: the
# markdown table on stdout; JSON and runs in ${GMC_CALIB_DIR:-out/calibration}.
# GMC_DATA_DIR (default ../shared/data) holds the real windows; missing ones are skipped.
set -euo pipefail
# shellcheck source=lib/prologue.sh
source "$(dirname "$0")/lib/prologue.sh" gmc-sim gmc-rgbd-mapping gmc-eval calibration_stats
out="${GMC_CALIB_DIR:-$root/out/calibration}"
data="${GMC_DATA_DIR:-$root/../shared/data}"
seeds=("$@")
[ ${#seeds[@]} -eq 0 ] && seeds=(1 2)
mkdir -p "$out"

# measure NAME PATH CONFIG CAMERA: statistics JSON and ATE (GMC off) into $out/NAME.*
measure() {
  local name="$1" path="$2" config="$3" camera="$4"
  echo "calibrate_sim: $name" >&2
  "$bin/calibration_stats" "$config" "$path" --camera "$camera" --json "$out/$name.json" >"$out/$name.txt"
  "$bin/gmc-rgbd-mapping" "$config" "$path" --out "$out/$name-nogmc" --set GMC.enabled=false \
    --set Output.map=false --set Playback.progress=false >"$out/$name-nogmc.log" 2>&1
  "$bin/gmc-eval" --gt "$path/groundtruth.txt" --est "$out/$name-nogmc/trajectory_tum.txt" |
    awk '/^ATE/ { print $3 }' >"$out/$name.ate"
}

rows=()
for window in bonn_crowd_240_389 bonn_crowd_301_460; do
  if [ -f "$data/$window/rgb.txt" ]; then
    measure "$window" "$data/$window" config/bonn.ini bonn
    rows+=("$window")
  else
    echo "calibrate_sim: $data/$window not found, skipped" >&2
  fi
done
read -r -a scenarios <<<"${GMC_CALIB_SCENARIOS:-crowd stop_and_go stop_and_go_hover}"
for scenario in "${scenarios[@]}"; do
  for seed in "${seeds[@]}"; do
    name="sim_${scenario}_seed$seed"
    "$bin/gmc-sim" "config/sim/$scenario.ini" --out "$out/data/$name" --seed "$seed" --frames 150 >/dev/null
    measure "$name" "$out/data/$name" config/default.ini fr3
    rows+=("$name")
  done
done

python3 - "$out" "${rows[@]}" <<'PY'
import json, sys
out, names = sys.argv[1], sys.argv[2:]
print("| sequence | frames | matches p50 | dynamic share p50 / p90 | static p10 / p50 "
      "| lower-half share p50 | frames < 50 static | people pixels p50 / p90 | camera mm / deg per frame p50 "
      "| tracked step p50 (mm) | ATE GMC off (m) |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for n in names:
    s = json.load(open(f"{out}/{n}.json"))
    ate = open(f"{out}/{n}.ate").read().strip()
    pp = s.get("people_pixels")
    people = f"{pp['p50']:.2f} / {pp['p90']:.2f}" if pp else "-"
    few = s["frames_static_below_50"]
    cam = (f"{s['camera_step_mm']['p50']:.1f} / {s['camera_rotation_deg']['p50']:.2f}"
           if "camera_step_mm" in s else "-")
    tracked = f"{s['tracked_step_mm']['p50']:.1f}" if "tracked_step_mm" in s else "-"
    print(f"| {n} | {s['frames']} | {s['matches']['p50']:.0f} "
          f"| {s['dynamic_share']['p50']:.2f} / {s['dynamic_share']['p90']:.2f} "
          f"| {s['static']['p10']:.0f} / {s['static']['p50']:.0f} | {s['lower_half_share']['p50']:.2f} "
          f"| {few} ({100 * few / (s['frames'] - 1):.0f} %) | {people} | {cam} | {tracked} | {float(ate):.3f} |")
PY
