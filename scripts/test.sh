#!/usr/bin/env bash
# Second README command: install what is missing, build, run every test.
# Real-data tests read GMC_DATA_DIR (default: ../shared/data next to the checkout)
# and skip with a message when it is absent.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/setup.sh"
"$root/scripts/build.sh"
if [ -z "${GMC_DATA_DIR:-}" ] && [ -d "$root/../shared/data" ]; then
  export GMC_DATA_DIR="$(cd "$root/../shared/data" && pwd)"
fi
cd "${GMC_BUILD_DIR:-$root/build}"
ctest --output-on-failure -j "${GMC_JOBS:-$(nproc)}" --timeout 900
