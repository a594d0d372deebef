# shellcheck shell=bash
# Shared start of the harness scripts (bench.sh, scaling.sh); sourced, not run:
#   source "$(dirname "$0")/lib/prologue.sh" TARGET...
# Strict mode; cd to the repository root; install what is missing (scripts/setup.sh);
# build TARGET... with scripts/build.sh (Release, output discarded; GMC_BUILD_DIR and
# GMC_JOBS apply as there; no target = all). Sets $root and $bin (the apps' folder).
# The caller's positional parameters are untouched.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
cd "$root"
"$root/scripts/setup.sh"
GMC_BUILD_TARGETS="$*" "$root/scripts/build.sh" >/dev/null
# shellcheck disable=SC2034  # $bin is for the sourcing script
bin="${GMC_BUILD_DIR:-$root/build}/bin"
