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
  pybind11-dev python3-dev python3-numpy python3-matplotlib python3-pytest  # import climbsim
  libpagmo-dev                 # CMA-ES for climbsim optimise
  libopenmpi-dev openmpi-bin   # mpirun -np N climbsim optimise|sweep (optional: CLIMBSIM_MPI)
  universal-ctags              # scripts/house_check.sh: the length of every function
  libtinyxml2-dev              # robot/: the generated robot models, built as an XML DOM
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

# `import climbsim` from anywhere: a .pth file in Python's site folder names build/python (the
# module is used where it is built, so a rebuild is picked up without reinstalling).
if [ -f "$build_dir/python/climbsim/__init__.py" ]; then
  python_dir=$(cd "$build_dir/python" && pwd)
  python=python3; [ -x /usr/bin/python3 ] && python=/usr/bin/python3  # Debian's, with numpy
  site=$($python -c 'import site; print(site.getsitepackages()[0])')
  if ! { mkdir -p "$site" 2>/dev/null && echo "$python_dir" >"$site/climbsim.pth" 2>/dev/null; }; then
    site=$($python -m site --user-site)
    mkdir -p "$site" && echo "$python_dir" >"$site/climbsim.pth"
  fi
  echo "setup: $python -c 'import climbsim' finds $python_dir (through $site/climbsim.pth)"
  # The python3 first on PATH (pyenv, conda) too, when it is the same CPython 3.X the module
  # was built for (its ABI); any Python: build/climbsim-python, or cmake --install (docs/python.md).
  first=$(command -v python3 || true)
  if [ -n "$first" ] && [ "$first" != "$python" ] &&
     [ "$("$first" -c 'import sys; print(sys.version_info[:2])' 2>/dev/null)" = \
       "$($python -c 'import sys; print(sys.version_info[:2])')" ]; then
    site=$("$first" -c 'import site; print(site.getsitepackages()[0])')
    if mkdir -p "$site" 2>/dev/null && echo "$python_dir" >"$site/climbsim.pth" 2>/dev/null; then
      echo "setup: $first -c 'import climbsim' finds $python_dir (through $site/climbsim.pth)"
    fi
  fi
fi
