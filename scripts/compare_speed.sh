#!/usr/bin/env bash
# What the effects cost with two climbsim executables, side by side: `bench speed` runs with
# REF and NEW alternately (ROUNDS times each, so both see the same machine load) and each
# profile line's share of mj_step is printed as the median of the rounds.
#   scripts/compare_speed.sh /path/to/reference/climbsim build/climbsim [EXAMPLE.yaml] [ROUNDS]
set -euo pipefail
if (($# < 2)); then
  echo "usage: $0 REFERENCE_CLIMBSIM NEW_CLIMBSIM [EXAMPLE.yaml] [ROUNDS]" >&2
  exit 2
fi
ref=$1
new=$2
example=${3:-examples/gecko_wall.yaml}
rounds=${4:-5}
cd "$(dirname "$0")/.."
work=$(mktemp -d "${TMPDIR:-/tmp}/climbsim_speed.XXXXXX")
trap 'rm -rf "$work"' EXIT
for ((i = 0; i < rounds; i++)); do
  for which in ref new; do
    exe=$ref
    [[ $which == new ]] && exe=$new
    "$exe" bench speed "$example" --duration 5 --repetitions 1 >"$work/$which.$i.txt"
  done
done
python3 - "$work" "$rounds" <<'PY'
import re, statistics, sys
work, rounds = sys.argv[1], int(sys.argv[2])
def shares(which):
    out = {}
    for i in range(rounds):
        for line in open(f"{work}/{which}.{i}.txt"):
            m = re.match(r"\s+(\S.*?)\s+[\d.]+ s\s+\+([\d.]+)% of mj_step", line)
            if m:
                out.setdefault(m.group(1), []).append(float(m.group(2)))
    return out
ref, new = shares("ref"), shares("new")
print(f"share of mj_step, median of {rounds} alternating rounds (each round's values in brackets)")
print(f"  {'part':<12} {'reference':>10} {'new':>10}")
for part in ref:
    r, n = ref[part], new.get(part, [float('nan')])
    print(f"  {part:<12} {statistics.median(r):9.2f}% {statistics.median(n):9.2f}%   "
          f"ref {', '.join(f'{x:.2f}' for x in r)}; new {', '.join(f'{x:.2f}' for x in n)}")
PY
