#!/usr/bin/env bash
# Runs every example (or the ones named) with two climbsim executables and compares what they
# wrote: trajectory.csv, events.csv and model.xml byte for byte, summary.json less its wall
# time. For a change that must not change any result (a refactor, a safety fix): build the
# reference from the commit before it, then
#   scripts/compare_outputs.sh /path/to/reference/climbsim build/climbsim
#   scripts/compare_outputs.sh REF NEW examples/gecko_wall.yaml examples/spider_wall.yaml
# Prints one line per example and exits 1 when any file differs (the runs are kept then).
# --model compiled compares model.xml as MuJoCo compiles it (mujoco-compile to MJB, byte for
# byte: the same model whatever its text's comments and layout, e.g. a generated robot beside
# the hand-written file it replaces); --model skip leaves model.xml out.
set -euo pipefail
model=xml
if [[ ${1:-} == --model ]]; then
  model=${2:-}
  shift 2 || true
fi
if (($# < 2)) || [[ $model != xml && $model != compiled && $model != skip ]]; then
  echo "usage: $0 [--model xml|compiled|skip] REFERENCE_CLIMBSIM NEW_CLIMBSIM [EXAMPLE.yaml ...]" >&2
  exit 2
fi
ref=$1
new=$2
shift 2
cd "$(dirname "$0")/.."
examples=("$@")
((${#examples[@]})) || examples=(examples/*.yaml)

work=$(mktemp -d "${TMPDIR:-/tmp}/climbsim_compare.XXXXXX")
status=0
for example in "${examples[@]}"; do
  name=$(basename "$example" .yaml)
  "$ref" simulate "$example" --out "$work/ref/$name" --quiet >"$work/$name.ref.log" 2>&1 &
  "$new" simulate "$example" --out "$work/new/$name" --quiet >"$work/$name.new.log" 2>&1 ||
    true
  wait || true
  differs=()
  for f in trajectory.csv events.csv; do
    cmp -s "$work/ref/$name/$f" "$work/new/$name/$f" || differs+=("$f")
  done
  case $model in
    xml) cmp -s "$work/ref/$name/model.xml" "$work/new/$name/model.xml" || differs+=(model.xml) ;;
    compiled)
      for side in ref new; do
        mujoco-compile "$work/$side/$name/model.xml" "$work/$side/$name.mjb" >/dev/null 2>&1 ||
          true
      done
      if [[ ! -s $work/ref/$name.mjb ]] || ! cmp -s "$work/ref/$name.mjb" "$work/new/$name.mjb"; then
        differs+=("model.xml (compiled)")
      fi
      ;;
  esac
  # summary.json less what depends on the machine's load.
  if ! python3 - "$work/ref/$name/summary.json" "$work/new/$name/summary.json" <<'EOF'; then
import json, sys
def load(path):
    with open(path) as f:
        d = json.load(f)
    for key in ("wall_time_s", "realtime_factor", "steps_per_s"):
        d.pop(key, None)
    # The servo margins: a statics check made before the run (simulate), not the run's result.
    d.pop("servo_margins", None)
    return d
sys.exit(0 if load(sys.argv[1]) == load(sys.argv[2]) else 1)
EOF
    differs+=(summary.json)
  fi
  if ((${#differs[@]})); then
    echo "$name: DIFFERS: ${differs[*]}"
    status=1
  else
    echo "$name: identical"
  fi
done
if ((status == 0)); then
  rm -rf "$work"
else
  echo "runs kept in $work"
fi
exit $status
