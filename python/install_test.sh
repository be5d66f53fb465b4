#!/usr/bin/env bash
# The Python module installed as a user installs it:
#   1. cmake --install --prefix VENV --component python into a venv made from the Python the
#      module was built for (--system-site-packages: NumPy comes from Debian, nothing can be
#      downloaded here), then that venv's python imports climbsim from its own site-packages,
#      with no PYTHONPATH, from another folder, and runs a scenario;
#   2. with no --prefix, the default destination is that Python's own site-packages (staged
#      under DESTDIR, so the test writes nothing outside its folder);
#   3. build/climbsim-python imports it with a python3 first on PATH that cannot.
#   install_test.sh BINARY_DIR PYTHON PLATLIB
set -euo pipefail
bin=$1 python=$2 sitearch=$3  # sysconfig platlib of PYTHON
work=$(mktemp -d "${TMPDIR:-/tmp}/climbsim_python_install_XXXXXX")
unset PYTHONPATH

"$python" -m venv --system-site-packages "$work/venv"
cmake --install "$bin" --prefix "$work/venv" --component python >"$work/install.log"
cd "$work"
"$work/venv/bin/python" - "$work/venv" <<'PY'
import os, sys
import climbsim
venv = os.path.realpath(sys.argv[1])
assert os.path.realpath(climbsim.__file__).startswith(venv + "/lib/"), climbsim.__file__
s = climbsim.scenario_from_dict({"robot": "gecko", "scene": "floor", "duration_s": 0.02,
                                 "cpg": {"gait": "trot"}})
s["cpg.frequency_hz"] = 0.8
summary = climbsim.Simulation(s).run()
assert summary["steps"] == 20 and summary["stable"], summary
print("venv:", climbsim.__file__)
PY

DESTDIR="$work/stage" cmake --install "$bin" --component python >"$work/install_default.log"
ls "$work/stage$sitearch"/climbsim/_core*.so >/dev/null
test -f "$work/stage$sitearch/climbsim/__init__.py"
echo "default: $sitearch/climbsim"

mkdir -p "$work/path"
printf '#!/bin/sh\necho "not this python" >&2\nexit 3\n' >"$work/path/python3"
chmod +x "$work/path/python3"
PATH="$work/path:$PATH" "$bin/climbsim-python" - "$bin" <<'PY'
import os, sys
import climbsim
want = os.path.realpath(sys.argv[1]) + "/python/"
assert os.path.realpath(climbsim.__file__).startswith(want), (climbsim.__file__, want)
print("launcher:", climbsim.__file__)
PY
rm -rf "$work"
echo PASS
