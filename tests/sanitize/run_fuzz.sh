#!/usr/bin/env bash
# The scenario loader under libFuzzer for a bounded time (issue 7 item 4), as one CTest test of
# the main build (fuzz_scenario_loader, label fuzz):
#   1. configure and build fuzz/ with clang++-14 in its own tree (incremental);
#   2. run scenario_fuzzer for SECONDS on a temporary copy of the seed corpus (examples/*.yaml
#      and every input in fuzz/regressions/), with the key dictionary fuzz/scenario.dict.
# A finding (crash, sanitizer report, leak, or a check of fuzz/scenario_check.h) fails the
# test; the input is kept in BUILD_DIR/findings/: copy it to fuzz/regressions/ and fix it.
#   tests/sanitize/run_fuzz.sh SOURCE_DIR BUILD_DIR [SECONDS]
set -euo pipefail
src=$1
build=$2
seconds=${3:-60}
cxx=${CLIMBSIM_FUZZ_CXX:-clang++-14}

mkdir -p "$build"
echo "fuzz: building $build with $cxx"
cmake -S "$src/fuzz" -B "$build" -DCMAKE_CXX_COMPILER="$cxx" >"$build/climbsim-configure.log" 2>&1 ||
  { cat "$build/climbsim-configure.log"; exit 1; }
if ! cmake --build "$build" -j 2 >"$build/climbsim-build.log" 2>&1; then
  cat "$build/climbsim-build.log"
  exit 1
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/corpus" "$build/findings"
cp "$src"/examples/*.yaml "$work/corpus/"
cp "$src"/fuzz/regressions/* "$work/corpus/" 2>/dev/null || true

export ASAN_OPTIONS=halt_on_error=1:detect_leaks=1
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
echo "fuzz: $seconds s on $(ls "$work/corpus" | wc -l) seed inputs"
status=0
(cd "$work" && "$build/scenario_fuzzer" -dict="$src/fuzz/scenario.dict" \
  -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
  -artifact_prefix="$build/findings/" "$work/corpus" >"$work/fuzz.log" 2>&1) || status=$?
grep -E "^(stat::|Done )" "$work/fuzz.log" || true
if [ $status -ne 0 ]; then
  tail -80 "$work/fuzz.log"
  echo "fuzz: FINDING, input kept in $build/findings/ (copy it to fuzz/regressions/)"
fi
exit $status
