#!/usr/bin/env bash
# Fuzzes our parsers with libFuzzer (clang, ASan + UBSan): builds the tests/fuzz targets
# into build-fuzz/ and runs each for SECONDS (default 60).
#   scripts/fuzz.sh [seconds_per_target]
# GMC_FUZZ_TARGETS="ini rawlog" picks targets; GMC_FUZZ_BUILD_DIR moves the build tree.
# Seeds come from tests/fuzz/corpus/<target>/ (never written to); what the fuzzer adds goes
# to build-fuzz/fuzz/corpus/<target>/, crashes to build-fuzz/fuzz/artifacts/<target>/.
# Exit status 1 when any target found something (its log and reproducer are printed).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
seconds="${1:-60}"
build="${GMC_FUZZ_BUILD_DIR:-$root/build-fuzz}"
jobs="${GMC_JOBS:-$(nproc)}"
read -r -a targets <<< "${GMC_FUZZ_TARGETS:-tum_list tum_trajectory ini rawlog}"

if ! command -v clang++ >/dev/null; then
  echo "fuzz.sh: clang++ not found (apt-get install clang)" >&2
  exit 1
fi
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=clang++ \
  -DGMC_FUZZ=ON -DGMC_BUILD_TESTS=OFF -DGMC_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build "$build" -j "$jobs" --target "${targets[@]/#/fuzz_}"

# The rawlog target runs in libFuzzer's fork mode and goes on after a crash, OOM or timeout,
# so one known problem of MRPT's (see doc/robustness.md) does not end the run; the others
# stop at their first failure. Each reproducer is then run again and sorted: "MRPT" when the failure lies inside MRPT's deserialiser
# (our reader names the object when MRPT's JPEG decoder calls exit(); corrupt length fields
# make MRPT allocate gigabytes or write through the null pointer its aligned allocator
# returns), "OURS" otherwise. Requests above 2 GB fail as
# std::bad_alloc, as they can outside the sanitizer, and the readers must report that as
# their documented error; real growth beyond -rss_limit_mb is an OOM.
export ASAN_OPTIONS="${ASAN_OPTIONS:-allocator_may_return_null=1:max_allocation_size_mb=2048:detect_leaks=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
limits=(-rss_limit_mb=2048 -malloc_limit_mb=4096 -timeout=10)
status=0
summary=""
for t in "${targets[@]}"; do
  work="$build/fuzz/corpus/$t"
  artifacts="$build/fuzz/artifacts/$t"
  log="$build/fuzz/$t.log"
  rm -rf "$artifacts"
  mkdir -p "$work" "$artifacts"
  start=$(date +%s)
  fork=()
  [ "$t" != rawlog ] || fork=(-fork=1 -ignore_crashes=1 -ignore_ooms=1 -ignore_timeouts=1)
  "$build/bin/fuzz_$t" "${fork[@]}" -max_total_time="$seconds" "${limits[@]}" \
    -print_final_stats=1 -artifact_prefix="$artifacts/" \
    "$work" "$root/tests/fuzz/corpus/$t" >"$log" 2>&1 || true
  elapsed=$(( $(date +%s) - start ))
  execs=$(sed -n -e 's/^stat::number_of_executed_units: *//p' -e 's/^#\([0-9][0-9]*\): cov:.*/\1/p' "$log" | tail -1)
  ours=0 mrpt=0
  for a in "$artifacts"/*; do
    [ -e "$a" ] || continue
    out="$("$build/bin/fuzz_$t" -runs=1 "${limits[@]}" "$a" 2>&1 || true)"
    # Whose code failed: the first stack frame that is either ours (gmc::) or MRPT's
    # (its libraries, its header templates instantiated in our binary). Without either
    # (ASan's OOM reports show only the allocating frames) it counts as MRPT's: the
    # readers' own code never allocates by a size read from the file.
    owner="$(grep -E '^ +#[0-9]+ 0x' <<<"$out" | grep -oE 'gmc::|libmrpt|include/mrpt' | head -1 || true)"
    if grep -q "MRPT ended the process while decoding" <<<"$out" ||
       [ "$owner" != "gmc::" ]; then
      mrpt=$((mrpt + 1))
      kind=MRPT
    else
      ours=$((ours + 1))
      kind=OURS
    fi
    echo "fuzz: $t: $kind $(basename "$a"): $(grep -m1 -E 'ERROR|runtime error|invariant|MRPT ended|what\(\)' <<<"$out" | cut -c1-160)"
  done
  result="ours: $ours, MRPT: $mrpt"
  [ "$ours" -eq 0 ] || status=1
  line="$(printf '%-16s %5ss %12s execs  %s' "$t" "$elapsed" "${execs:-?}" "$result")"
  echo "fuzz: $line"
  summary+="$line"$'\n'
done
echo "--- fuzz summary (target, seconds, executions, failing inputs found: ours / inside MRPT)"
printf '%s' "$summary"
echo "reproducers: $build/fuzz/artifacts/<target>/ (run: $build/bin/fuzz_<target> FILE)"
exit "$status"
