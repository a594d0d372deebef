#!/usr/bin/env bash
# Configures and builds GMC-RGBD (Release, assertions on) into build/; apps land in build/bin.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${GMC_BUILD_DIR:-$root/build}"
jobs="${GMC_JOBS:-$(nproc)}"
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build "$build" -j "$jobs"
