#!/usr/bin/env bash
# A fuzz target of fuzz/ under libFuzzer for a bounded time (issue 7 item 4), as one CTest test
# of the main build (fuzz_scenario_loader and fuzz_run_files, label fuzz):
#   1. configure fuzz/ with clang++-14 in its own tree and build the target (incremental);
#   2. run it for SECONDS on a temporary copy of its seed corpus, with its dictionary:
#      scenario   scenario_fuzzer:  examples/*.yaml and fuzz/regressions/*, fuzz/scenario.dict
#      run_files  run_files_fuzzer: fuzz/run_files_seeds/* and fuzz/run_files_regressions/*,
#                 fuzz/run_files.dict
# A finding (crash, sanitizer report, leak, or a check of fuzz/*_check.h) fails the test; the
# input is kept in BUILD_DIR/findings/: copy it to the target's regressions folder and fix it.
#   tests/sanitize/run_fuzz.sh SOURCE_DIR BUILD_DIR [SECONDS] [scenario|run_files]
set -euo pipefail
src=$1
build=$2
seconds=${3:-60}
target=${4:-scenario}
cxx=${CLIMBSIM_FUZZ_CXX:-clang++-14}

case $target in
  scenario)
    fuzzer=scenario_fuzzer dict=scenario.dict seeds=("$src"/examples/*.yaml)
    regressions=$src/fuzz/regressions ;;
  run_files)
    fuzzer=run_files_fuzzer dict=run_files.dict seeds=("$src"/fuzz/run_files_seeds/*)
    regressions=$src/fuzz/run_files_regressions ;;
  *) echo "fuzz: unknown target $target (scenario, run_files)"; exit 2 ;;
esac

mkdir -p "$build"
echo "fuzz: building $fuzzer in $build with $cxx"
cmake -S "$src/fuzz" -B "$build" -DCMAKE_CXX_COMPILER="$cxx" >"$build/climbsim-configure.log" 2>&1 ||
  { cat "$build/climbsim-configure.log"; exit 1; }
if ! cmake --build "$build" --target "$fuzzer" -j 2 >"$build/climbsim-build-$target.log" 2>&1; then
  cat "$build/climbsim-build-$target.log"
  exit 1
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/corpus" "$work/tmp" "$build/findings"
cp "${seeds[@]}" "$work/corpus/"
cp "$regressions"/* "$work/corpus/" 2>/dev/null || true

export ASAN_OPTIONS=halt_on_error=1:detect_leaks=1
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
echo "fuzz: $seconds s on $(ls "$work/corpus" | wc -l) seed inputs"
status=0
# TMPDIR: the files a target writes go with the work folder.
(cd "$work" && TMPDIR="$work/tmp" "$build/$fuzzer" -dict="$src/fuzz/$dict" \
  -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
  -artifact_prefix="$build/findings/" "$work/corpus" >"$work/fuzz.log" 2>&1) || status=$?
grep -E "^(stat::|Done )" "$work/fuzz.log" || true
if [ $status -ne 0 ]; then
  tail -80 "$work/fuzz.log"
  echo "fuzz: FINDING, input kept in $build/findings/ (copy it to $regressions/)"
fi
exit $status
