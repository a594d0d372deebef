#!/usr/bin/env bash
# Configures and builds GMC-RGBD (Release, assertions on) into build/; apps land in build/bin.
# GMC_BUILD_TARGETS="a b" builds only those targets (the scripts that need only apps).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${GMC_BUILD_DIR:-$root/build}"
jobs="${GMC_JOBS:-$(nproc)}"
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
read -r -a targets <<< "${GMC_BUILD_TARGETS:-all}"
cmake --build "$build" -j "$jobs" --target "${targets[@]}"
