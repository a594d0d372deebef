#!/usr/bin/env bash
# Second README command: install what is missing, build, run every test.
# Real-data tests read GMC_DATA_DIR (default: ../shared/data next to the checkout)
# and skip with a message when it is absent.
# GMC_TEST_EXTENDED=1 also fuzzes every parser for 60 s after ctest (scripts/fuzz.sh,
# clang; about 6 minutes with the build). Default runs do not fuzz.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/setup.sh"
"$root/scripts/build.sh"
if [ -z "${GMC_DATA_DIR:-}" ] && [ -d "$root/../shared/data" ]; then
  export GMC_DATA_DIR="$(cd "$root/../shared/data" && pwd)"
fi
cd "${GMC_BUILD_DIR:-$root/build}"
ctest --output-on-failure -j "${GMC_JOBS:-$(nproc)}" --timeout 900
if [ "${GMC_TEST_EXTENDED:-0}" = 1 ]; then
  "$root/scripts/fuzz.sh" 60
fi
