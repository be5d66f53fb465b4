#!/usr/bin/env bash
# Installs the Debian 12 packages climbsim needs (only those missing), then configures and
# builds climbsim in Release in build/. Run as root on a fresh machine; safe to rerun.
#   scripts/setup.sh            # install + build
#   BUILD_DIR=build-asan CMAKE_ARGS=-DCLIMBSIM_SANITIZE=ON scripts/setup.sh
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  build-essential cmake pkg-config
  libmujoco-dev libqhull-dev libgl-dev libopengl-dev libegl-dev libegl-mesa0 libgl1-mesa-dri
  libeigen3-dev libboost-dev libnlopt-cxx-dev libyaml-cpp-dev libcli11-dev nlohmann-json3-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  gnuplot-nox ffmpeg
  clang-14 libclang-rt-14-dev  # libFuzzer and its sanitizers: the fuzz_scenario_loader test
  libmujoco-samples  # mujoco-simulate and mujoco-compile: open a robot or a run's model.xml
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -q
  $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

build_dir=${BUILD_DIR:-build}
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release ${CMAKE_ARGS:-} >/dev/null
cmake --build "$build_dir" -j "$(nproc)"
