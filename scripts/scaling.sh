#!/usr/bin/env bash
# Scaling figures of doc/performance.md: ms per frame and resident memory against the
# sequence length (300, 3,000, 10,000 frames; a generated 240-frame walkers_xyz loop
# played repeatedly) and against map volume (voxel size 0.10 / 0.05 / 0.025 m, 300
# frames), plus the odometry alone over 3,000 frames. Writes out/scaling/results.md and
# the memory curve of the 10,000-frame run to doc/images/memory_10000.png.
#   ./scripts/scaling.sh            (about 25 minutes on 2 cores)
# GMC_SCALING_FRAMES="300 3000" shortens the length series (the picture then comes
# from the longest run).
set -euo pipefail
# cd to the repository root, setup.sh, build these apps; sets $root and $bin
# shellcheck source=lib/prologue.sh
source "$(dirname "$0")/lib/prologue.sh" gmc-sim gmc-rgbd-mapping
out="${GMC_SCALING_DIR:-$root/out/scaling}"
read -r -a lengths <<< "${GMC_SCALING_FRAMES:-300 3000 10000}"
mkdir -p "$out"
loop="$out/loop240"
[ -f "$loop/rgb.txt" ] || "$bin/gmc-sim" config/sim/walkers_xyz.ini --out "$loop" --frames 240 >/dev/null

run() {  # run NAME FRAMES [--set ...]
  local name="$1" frames="$2"; shift 2
  echo "scaling: $name ($frames frames)" >&2
  rm -rf "${out:?}/$name"
  "$bin/gmc-rgbd-mapping" config/default.ini "$loop" --out "$out/$name" --set Playback.progress=false \
    --set Dataset.repeat=100 --set Dataset.max_frames="$frames" --set Output.memory_every=100 "$@" \
    >"$out/$name.log" 2>&1
}
stage() {  # stage SUMMARY NAME -> "median (p95)"
  python3 -c 'import json, sys; s = json.load(open(sys.argv[1]))["ms"][sys.argv[2]]
print("%.1f (%.1f)" % (s["median"], s["p95"]), end="")' "$1" "$2"
}
value() { grep -o "\"$2\": [0-9.e+-]*" "$1" | head -1 | awk '{ print $2 }'; }
row() {  # row LABEL SUMMARY
  local s="$2" map="-"
  [ -z "$(value "$s" leaf_nodes)" ] ||
    map="$(value "$s" occupied_leaves) / $(value "$s" leaf_nodes), $(( $(value "$s" memory_bytes) / 1024 )) KiB"
  local mapping="-"
  [ "$map" = "-" ] || mapping="$(stage "$s" mapping)"
  printf '| %s | %s | %s | %s | %s | %.0f MB | %s |\n' "$1" "$(stage "$s" odometry)" "$mapping" \
    "$(stage "$s" dynamic_mask)" "$(stage "$s" total)" "$(value "$s" peak_rss_mb)" "$map"
}

odometry_frames="${GMC_SCALING_ODOMETRY_FRAMES:-3000}" volume_frames="${GMC_SCALING_VOLUME_FRAMES:-300}"
longest=""
for n in "${lengths[@]}"; do run "run_$n" "$n"; longest="run_$n"; done
run odo "$odometry_frames" --set Output.map=false
for r in 0.1 0.05 0.025; do run "res_$r" "$volume_frames" --set Mapping.resolution="$r"; done

md="$out/results.md.tmp"
{
  echo "# Scaling ($(date -u +%Y-%m-%d), $(nproc) cores, commit $(git rev-parse --short HEAD 2>/dev/null || echo '?'))"
  echo
  echo "Command: \`./scripts/scaling.sh\`. Input: \`gmc-sim config/sim/walkers_xyz.ini --frames 240\` played repeatedly."
  echo
  echo "| run | odometry ms median (p95) | mapping ms median (p95) | dynamic mask ms median (p95) | total ms median (p95) | peak resident memory | map: occupied / leaves, memory |"
  echo "|---|---|---|---|---|---|---|"
  for n in "${lengths[@]}"; do row "$n frames" "$out/run_$n/summary.json"; done
  row "$odometry_frames frames, odometry only" "$out/odo/summary.json"
  for r in 0.1 0.05 0.025; do row "$volume_frames frames, voxel $r m" "$out/res_$r/summary.json"; done
  echo
  echo "Memory curves: \`$out/<run>/memory.csv\` (frame, resident MB, map nodes) and \`memory.png\`."
} > "$md"
mv "$md" "$out/results.md"
mkdir -p doc/images
cp "$out/$longest/memory.png" "doc/images/memory_${longest#run_}.png.tmp" && mv "doc/images/memory_${longest#run_}.png.tmp" "doc/images/memory_${longest#run_}.png"
cat "$out/results.md"
