#!/usr/bin/env bash
# climbsim as a CMake package: installs this build into a fresh prefix, builds
# examples/cpp_controller against it as a separate project (find_package(climbsim)), runs
# its bang-bang gecko for 5 s on the floor and checks that it walked forward.
#   install_example_test.sh SOURCE_DIR BINARY_DIR
set -euo pipefail
src=$1 bin=$2
work=$(mktemp -d "${TMPDIR:-/tmp}/climbsim_package_XXXXXX")
prefix=$work/prefix
cmake --install "$bin" --prefix "$prefix" >"$work/install.log"
test -f "$prefix/lib/cmake/climbsim/climbsimConfig.cmake"
test -f "$prefix/lib/cmake/climbsim/climbsimConfigVersion.cmake"
test -f "$prefix/include/climbsim/sim/controller.h"
test -f "$prefix/share/climbsim/mjcf/gecko.xml"

launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S "$src/examples/cpp_controller" -B "$work/build" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" "${launcher[@]}" >"$work/configure.log"
cmake --build "$work/build" >"$work/build.log"

# Run from elsewhere, the source tree's models hidden: the package's own are used.
out=$(cd "$work" && "$work/build/bang_bang_gecko" 5 "$work/run")
echo "$out"
grep -q '^stable 1$' <<<"$out"
grep -q 'bang_bang_trot' <<<"$out"
distance=$(awk '/^distance_m/ {print $2}' <<<"$out")
# A trot of 0.6 s with ±0.3 rad hip strokes: well over 5 cm in 5 s (measured 0.57 m).
awk -v d="$distance" 'BEGIN { exit !(d > 0.05) }' || {
  echo "FAIL: the gecko moved $distance m (want > 0.05 m)"; exit 1; }
test -f "$work/run/model.xml"
grep -q "^mjcf_dir $prefix/share/climbsim/mjcf$" <<<"$out"  # the package's models were used
rm -rf "$work"
echo "PASS"
