#!/usr/bin/env bash
# First README command: install what is missing, build, generate a dynamic sequence with
# walkers (embedded default data), run the whole pipeline on it, evaluate.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/setup.sh"
"$root/scripts/build.sh"
bin="${GMC_BUILD_DIR:-$root/build}/bin"
out="${GMC_DEMO_DIR:-$root/out/demo}"
frames="${GMC_DEMO_FRAMES:-300}"
mkdir -p "$out"
echo "== generating $frames frames of config/sim/walkers_xyz.ini into $out/sequence"
"$bin/gmc-sim" "$root/config/sim/walkers_xyz.ini" --out "$out/sequence" --frames "$frames"
echo "== gmc-rgbd-mapping (GMC on)"
"$bin/gmc-rgbd-mapping" "$root/config/default.ini" "$out/sequence" --out "$out/run" \
  --set Dataset.anchor_to_groundtruth=true --set Output.overlay_every=30
echo "== trajectory error against ground truth"
"$bin/gmc-eval" --gt "$out/sequence/groundtruth.txt" --est "$out/run/trajectory_tum.txt" \
  --json "$out/run/eval.json" --plot "$out/run/trajectory.png"
echo "== static map export"
"$bin/gmc-map-export" "$out/run/map.bt" --ply "$out/run/map.ply" --grid "$out/run/grid.png" \
  --grid-yaml "$out/run/grid.yaml" --top-view "$out/run/map_top.png" --height-band 0.1,2.5
echo "== outputs in $out/run: trajectory_tum.txt, map.bt (octovis), map.ply, grid.png/.yaml, map_top.png, summary.json, eval.json, trajectory.png, overlays/"
