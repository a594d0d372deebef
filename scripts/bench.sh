#!/usr/bin/env bash
# Benchmark harness: runs the sequences x methods of one or more config/bench/*.ini files
# and writes the paper's tables (ATE, RPE translation, RPE rotation, runtime per stage),
# the simulator's dynamic-match and map metrics, CSV, and trajectory plots.
#
#   ./scripts/bench.sh                       # config/bench/sim.ini + config/bench/shared_data.ini
#   ./scripts/bench.sh config/bench/tum_bonn_full.ini
#
# Output: ${GMC_BENCH_DIR:-out/bench}/results.md (all configs), and per config
# <name>/results.md, <name>/results.csv, <name>/plots/<sequence>-<method>.png.
# Methods: gmc (our odometry with GMC), nogmc (the same with [GMC] enabled = false),
# cv_rgbd / cv_icp / cv_rgbd_icp (OpenCV's cv::rgbd odometries on the same frames).
# Timing runs are repeated ([Bench] repeats) and reported as the median with the
# min-max spread; trajectories are deterministic (checked: every repeat must give a
# byte-identical trajectory). [Bench] start_offsets adds an ATE spread over runs started
# a few frames later (keyframes fall elsewhere). [seq] window = N (and window_step = S,
# default 10) adds the window study of scripts/window_eval.py: the whole sequence and
# N-frame windows starting every S frames, each next to the ATE of a camera that never
# moves over the same frames. [seq] gt_frame = bonn takes the RPE in the camera's frame
# (Bonn's ground truth tracks a marker body). Timing is only fair on an idle machine.
set -euo pipefail
# cd to the repository root, setup.sh, build these apps; sets $root and $bin
# shellcheck source=lib/prologue.sh
source "$(dirname "$0")/lib/prologue.sh" gmc-sim gmc-rgbd-mapping gmc-eval gmc-baseline-odometry gmc-map-export
out="${GMC_BENCH_DIR:-$root/out/bench}"
export GMC_DATA_DIR="${GMC_DATA_DIR:-$root/../shared/data}"
export GMC_DATASETS_DIR="${GMC_DATASETS_DIR:-$HOME/datasets}"
configs=("$@")
[ ${#configs[@]} -eq 0 ] && configs=(config/bench/sim.ini config/bench/shared_data.ini)

# --- INI and JSON reading (configparser, json): scripts/lib/bench_data.py
data() { python3 "$root/scripts/lib/bench_data.py" "$@"; }
ini_get() { data ini-get "$@"; }            # ini_get FILE SECTION KEY DEFAULT
ini_sections() { data ini-sections "$1"; }  # every section but [Bench]
expand() { local s="$1"; s="${s//\$\{GMC_DATA_DIR\}/$GMC_DATA_DIR}"; echo "${s//\$\{GMC_DATASETS_DIR\}/$GMC_DATASETS_DIR}"; }
csv_list() { echo "$1" | tr ',' ' '; }

# --- small numeric helpers
json() { data json "$@"; }                  # json FILE DOTTED.PATH [PRINTF-FORMAT]
stage_median() { data json "$1" "ms.$2.median"; }
stage_p95() { data json "$1" "ms.$2.p95"; }
# spread "v1 v2 ...": "median [min-max]" with the given printf format
spread() {
  local fmt="$1"; shift
  printf '%s\n' "$@" | sort -g | awk -v f="$fmt" '{ v[NR] = $1 } END {
    if (NR == 0) { print "-"; exit }
    m = (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2
    if (NR == 1) printf(f "\n", m); else printf(f " [" f "-" f "]\n", m, v[1], v[NR]) }'
}
median_of() { printf '%s\n' "$@" | sort -g | awk '{ v[NR] = $1 } END { if (NR) print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
# eval_metrics GT EST [PLOT] -> "ate_rmse ate_mae rpe_t_rmse rpe_t_mae rpe_r_rmse rpe_r_mae"
# With $gt_frame other than camera ([seq] gt_frame, e.g. bonn: the ground truth tracks a
# marker body) the RPE is taken in the camera's frame (gmc-eval --gt-frame), where
# relative motions compare; the ATE stays against the ground truth as published, as
# every window and earlier figure is (the alignment absorbs the lever arm: 0.2 mm on Bonn).
eval_metrics() {
  local plot=() j="$2.eval.json"
  [ -n "${3-}" ] && plot=(--plot "$3")
  "$bin/gmc-eval" --gt "$1" --est "$2" --json "$j" "${plot[@]}" >/dev/null
  if [ "${gt_frame:-camera}" = camera ]; then data eval "$j"; return; fi
  local jc="$2.eval_$gt_frame.json" ate rpe
  "$bin/gmc-eval" --gt "$1" --est "$2" --gt-frame "$gt_frame" --json "$jc" >/dev/null
  read -r -a ate <<<"$(data eval "$j")"
  read -r -a rpe <<<"$(data eval "$jc")"
  echo "${ate[0]} ${ate[1]} ${rpe[2]} ${rpe[3]} ${rpe[4]} ${rpe[5]}"
}
# runtime_cells PREFIX: " | median [min-max] (p95)" per stage over the runs PREFIX-1..PREFIX-$repeats
runtime_cells() {
  local cells="" st r meds p95s
  for st in frontend guess gmc refinement odometry dynamic_mask mapping total; do
    meds=() p95s=()
    for r in $(seq 1 "$repeats"); do
      meds+=("$(stage_median "$1-$r/summary.json" "$st")")
      p95s+=("$(stage_p95 "$1-$r/summary.json" "$st")")
    done
    cells="$cells | $(spread '%.2f' "${meds[@]}") ($(printf '%.2f' "$(median_of "${p95s[@]}")"))"
  done
  echo "$cells"
}
# runs_fps PREFIX: frames per second over the same runs, "median [min-max]"
runs_fps() {
  local r fps=()
  for r in $(seq 1 "$repeats"); do fps+=("$(json "$1-$r/summary.json" fps)"); done
  spread '%.1f' "${fps[@]}"
}
method_name() {
  case "$1" in
    gmc) echo "GMC odometry" ;; nogmc) echo "without GMC" ;; cv_rgbd) echo "OpenCV RgbdOdometry" ;;
    cv_icp) echo "OpenCV ICPOdometry" ;; cv_rgbd_icp) echo "OpenCV RgbdICPOdometry" ;; *) echo "$1" ;;
  esac
}

all_md="$out/results.md.tmp"
mkdir -p "$out"
echo "# GMC-RGBD benchmark ($(date -u +%Y-%m-%d), $(nproc) cores, $(uname -m), commit $(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo '?'))" > "$all_md"

for config in "${configs[@]}"; do
  [ -f "$config" ] || { echo "bench: $config: no such file" >&2; exit 1; }
  name="$(basename "$config" .ini)"
  dir="$out/$name"
  rm -rf "$dir/run" "$dir/plots"
  mkdir -p "$dir/run" "$dir/plots" "$dir/data"
  methods="$(csv_list "$(ini_get "$config" Bench methods "gmc, nogmc")")"
  repeats="$(ini_get "$config" Bench repeats 1)"
  offsets="$(csv_list "$(ini_get "$config" Bench start_offsets "")")"
  csv="$dir/results.csv.tmp"
  echo "sequence,method,frames,ate_rmse_m,ate_mae_m,rpe_t_rmse_m,rpe_t_mae_m,rpe_r_rmse_deg,rpe_r_mae_deg,ms_per_frame_median,ms_min,ms_max" > "$csv"
  t1="" t2="" t3="" t4="" t5="" t6="" t7="" skipped=""
  for seq in $(ini_sections "$config"); do
    gen="$(ini_get "$config" "$seq" generate "")"
    cfg="$(ini_get "$config" "$seq" config config/default.ini)"
    cam="$(ini_get "$config" "$seq" camera fr3)"
    gt_frame="$(ini_get "$config" "$seq" gt_frame camera)"
    if [ -n "$gen" ]; then
      path="$dir/data/$seq"
      echo "bench: $name/$seq: generating" >&2
      "$bin/gmc-sim" "$gen" --out "$path" --frames "$(ini_get "$config" "$seq" frames 300)" >/dev/null
    else
      path="$(expand "$(ini_get "$config" "$seq" path "")")"
      if [ ! -f "$path/rgb.txt" ] || [ ! -f "$path/groundtruth.txt" ]; then
        skipped="$skipped\n- $seq: $path not found (TUM layout with groundtruth.txt expected), skipped"
        echo "bench: $name/$seq: $path not found, skipped" >&2
        continue
      fi
    fi
    gt="$path/groundtruth.txt"
    sim_extra=()
    [ -n "$gen" ] && sim_extra=(--set Dataset.anchor_to_groundtruth=true)
    row1="| $seq" row2="| $seq" row3="| $seq"
    for m in $methods; do
      echo "bench: $name/$seq: $m" >&2
      times=()
      traj=""
      case "$m" in
        gmc|nogmc)
          extra=()
          [ "$m" = nogmc ] && extra=(--set GMC.enabled=false)
          first_sum=""
          for r in $(seq 1 "$repeats"); do
            run="$dir/run/$seq-$m-$r"
            "$bin/gmc-rgbd-mapping" "$cfg" "$path" --out "$run" --set Playback.progress=false \
              "${sim_extra[@]}" "${extra[@]}" >"$run.log" 2>&1
            times+=("$(stage_median "$run/summary.json" total)")
            sum="$(md5sum < "$run/trajectory_tum.txt")"
            [ -z "$first_sum" ] && first_sum="$sum"
            [ "$sum" = "$first_sum" ] || { echo "bench: $seq/$m: repeat $r gave a different trajectory" >&2; exit 1; }
          done
          traj="$dir/run/$seq-$m-1/trajectory_tum.txt"
          frames="$(json "$dir/run/$seq-$m-1/summary.json" frames)"
          ;;
        cv_*)
          for r in $(seq 1 "$repeats"); do
            t="$dir/run/$seq-$m-$r.txt"
            "$bin/gmc-baseline-odometry" "$path" --camera "$cam" --method "${m#cv_}" --out "$t" \
              --json "$t.json" >"$t.log" 2>&1
            times+=("$(json "$t.json" ms_median %.2f)")  # as the app prints it
          done
          traj="$dir/run/$seq-$m-1.txt"
          frames="$(grep -vc '^#' "$traj")"
          ;;
        *) echo "bench: $config: unknown method '$m'" >&2; exit 1 ;;
      esac
      read -r ar am tr tm rr rm <<<"$(eval_metrics "$gt" "$traj" "$dir/plots/$seq-$m.png")"
      row1="$row1 | $ar / $am" row2="$row2 | $tr / $tm" row3="$row3 | $rr / $rm"
      read -r tmed tmin tmax <<<"$(printf '%s\n' "${times[@]}" | sort -g | awk '{ v[NR] = $1 } END {
        m = (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2; print m, v[1], v[NR] }')"
      echo "$seq,$m,$frames,$ar,$am,$tr,$tm,$rr,$rm,$tmed,$tmin,$tmax" >> "$csv"
      if [ "$m" = gmc ] || [ "$m" = nogmc ]; then
        t4="$t4\n| $seq | $(method_name "$m")$(runtime_cells "$dir/run/$seq-$m") | $(runs_fps "$dir/run/$seq-$m") |"
        # The odometry alone, as the OpenCV baselines run: no map thread sharing the cores.
        if [ "$m" = gmc ]; then
          for r in $(seq 1 "$repeats"); do
            "$bin/gmc-rgbd-mapping" "$cfg" "$path" --out "$dir/run/$seq-$m-nomap-$r" --set Playback.progress=false \
              --set Output.map=false "${sim_extra[@]}" >"$dir/run/$seq-$m-nomap-$r.log" 2>&1
          done
          t4="$t4\n| $seq | $(method_name "$m"), map off$(runtime_cells "$dir/run/$seq-$m-nomap") | $(runs_fps "$dir/run/$seq-$m-nomap") |"
        fi
      else
        t4="$t4\n| $seq | $(method_name "$m") | | | | | $(spread '%.2f' "${times[@]}") | | | | |"
      fi
    done
    t1="$t1\n$row1 |" t2="$t2\n$row2 |" t3="$t3\n$row3 |"
    # Simulated: dynamic-match and mask-pixel scores, map metrics (GMC; without GMC; GMC
    # poses without mask; GMC with the keypoint-grown mask only, no free-space check).
    if [ -n "$gen" ]; then
      nm="$dir/run/$seq-nomask" kp="$dir/run/$seq-keypointmask"
      "$bin/gmc-rgbd-mapping" "$cfg" "$path" --out "$nm" --set Playback.progress=false "${sim_extra[@]}" \
        --set Mapping.use_dynamic_mask=false >"$nm.log" 2>&1
      "$bin/gmc-rgbd-mapping" "$cfg" "$path" --out "$kp" --set Playback.progress=false "${sim_extra[@]}" \
        --set DynamicMask.free_space_check=false >"$kp.log" 2>&1
      on="$dir/run/$seq-gmc-1/summary.json" off="$dir/run/$seq-nogmc-1/summary.json"
      [ -f "$off" ] || off="$on"
      pixels="$(json "$on" dynamic_pixels_vs_masks.precision %.3f) | $(json "$on" dynamic_pixels_vs_masks.recall %.3f)"
      ghosts() { json "$1" map_quality.ghost_voxels; }
      coverage() { json "$1" map_quality.static_coverage %.3f; }
      t5="$t5\n| $seq | $(json "$on" dynamic_matches_vs_masks.precision %.3f) | $(json "$on" dynamic_matches_vs_masks.recall %.3f) | $pixels | $(ghosts "$on") / $(ghosts "$off") / $(ghosts "$nm/summary.json") / $(ghosts "$kp/summary.json") | $(coverage "$on") / $(coverage "$off") |"
    fi
    # Overlay picture ([seq] overlay_picture = PNG, overlay_frame = N): keypoints and mask
    # of frame N, with the ground-truth outline on simulated input.
    picture="$(ini_get "$config" "$seq" overlay_picture "")"
    if [ -n "$picture" ]; then
      n="$(ini_get "$config" "$seq" overlay_frame 40)" ov="$dir/run/$seq-overlay"
      "$bin/gmc-rgbd-mapping" "$cfg" "$path" --out "$ov" --set Playback.progress=false "${sim_extra[@]}" \
        --set Output.map=false --set Dataset.max_frames="$((n + 1))" --set Output.overlay_every="$n" >"$ov.log" 2>&1
      cp "$(ls "$ov"/overlays/*.png | sort | tail -1)" "$dir/plots/$seq-overlay.png"
      cp "$dir/plots/$seq-overlay.png" "$root/$picture"
    fi
    # Map pictures: top views with and without GMC side by side ([seq] map_picture = PNG
    # copies it there too, e.g. into doc/images for the README).
    on_map="$dir/run/$seq-gmc-1/map.bt" off_map="$dir/run/$seq-nogmc-1/map.bt"
    if [ -f "$on_map" ] && [ -f "$off_map" ]; then
      top="$dir/plots/$seq-map-top.png"
      "$bin/gmc-map-export" "$on_map" --top-view "$top" --compare "$off_map" --titles "with GMC,without GMC" \
        --up "$(ini_get "$config" "$seq" map_up z)" >/dev/null
      picture="$(ini_get "$config" "$seq" map_picture "")"
      [ -z "$picture" ] || cp "$top" "$root/$picture"
    fi
    # Start-offset study: the same sequence started k frames later.
    if [ -n "$offsets" ]; then
      for m in gmc nogmc; do
        [[ " $methods " == *" $m "* ]] || continue
        extra=()
        [ "$m" = nogmc ] && extra=(--set GMC.enabled=false)
        ates=()
        for k in $offsets; do
          run="$dir/run/$seq-$m-offset$k"
          "$bin/gmc-rgbd-mapping" "$cfg" "$path" --out "$run" --set Playback.progress=false \
            --set Output.map=false --set Dataset.first_frame="$k" "${extra[@]}" >"$run.log" 2>&1
          "$bin/gmc-eval" --gt "$gt" --est "$run/trajectory_tum.txt" --json "$run/eval.json" >/dev/null
          ates+=("$(json "$run/eval.json" ate.rmse)")
        done
        t6="$t6\n| $seq | $(method_name "$m") | $(printf '%.4f ' "${ates[@]}")| $(spread '%.4f' "${ates[@]}") |"
      done
    fi
    # Window study (GMC odometry, map off): the whole sequence and windows, each with the
    # standing-still ATE of its own frames.
    window="$(ini_get "$config" "$seq" window "")"
    if [ -n "$window" ]; then
      wj="$dir/run/$seq-windows.json"
      python3 "$root/scripts/window_eval.py" --bin "$bin" --config "$cfg" --window "$window" \
        --step "$(ini_get "$config" "$seq" window_step 10)" --json "$wj" "$path" >"$dir/run/$seq-windows.md"
      t7="$t7\n$(data windows "$wj" "$seq")"
    fi
  done

  header="| sequence |"; rule="|---|"
  for m in $methods; do header="$header $(method_name "$m") |"; rule="$rule---|"; done
  md="$dir/results.md.tmp"
  {
    echo "## $name ($config)"
    echo
    echo "Command: \`./scripts/bench.sh $config\`; plots in \`$name/plots/\`, CSV in \`$name/results.csv\`."
    echo
    echo "### ATE (m): RMSE / MAE (median absolute error)"
    echo; echo "$header"; echo "$rule"; echo -e "${t1#\\n}"
    echo
    echo "### RPE translation over 1 s (m): RMSE / MAE"
    echo; echo "$header"; echo "$rule"; echo -e "${t2#\\n}"
    echo
    echo "### RPE rotation over 1 s (deg): RMSE / MAE"
    echo; echo "$header"; echo "$rule"; echo -e "${t3#\\n}"
    echo
    echo "### Runtime per frame (ms): median over $repeats runs [min-max of the runs' medians] (p95)"
    echo
    echo "\"map off\": the same odometry run without the map thread (\`Output.map=false\`), as the OpenCV"
    echo "baselines run; the row above it shares the two cores with the OctoMap insertion."
    echo
    echo "| sequence | method | frontend | guess | GMC | refinement | tracking (odometry) | dynamic mask | mapping | total | frames/s |"
    echo "|---|---|---|---|---|---|---|---|---|---|---|"
    echo -e "${t4#\\n}"
    if [ -n "$t5" ]; then
      echo
      echo "### Simulated sequences: dynamic matches and map"
      echo
      echo "| sequence | dyn. match precision | dyn. match recall | mask pixel precision | mask pixel recall | ghost voxels GMC / without GMC / GMC poses without mask / keypoint mask only | static coverage GMC / without GMC |"
      echo "|---|---|---|---|---|---|---|"
      echo -e "${t5#\\n}"
    fi
    if [ -n "$t6" ]; then
      echo
      echo "### ATE (m) over start offsets $(echo $offsets | tr -s ' ' ',') (frames skipped at the start)"
      echo
      echo "| sequence | method | per offset | median [min-max] |"
      echo "|---|---|---|---|"
      echo -e "${t6#\\n}"
    fi
    if [ -n "$t7" ]; then
      echo
      echo "### GMC odometry over windows, next to standing still (scripts/window_eval.py)"
      echo
      echo "ATE (m) of the whole sequence and of windows of [seq] window frames starting every"
      echo "window_step frames; in brackets, a camera that never moves over the same frames."
      echo
      echo "| sequence | whole (standing still) | windows median / max | windows below standing still | per window: first frame: ATE (standing still) |"
      echo "|---|---|---|---|---|"
      echo -e "${t7#\\n}"
    fi
    [ -n "$skipped" ] && echo -e "\nSkipped:$skipped"
    echo
  } > "$md"
  mv "$md" "$dir/results.md"
  mv "$csv" "$dir/results.csv"
  { echo; cat "$dir/results.md"; } >> "$all_md"
done
mv "$all_md" "$out/results.md"
cat "$out/results.md"
