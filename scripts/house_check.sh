#!/usr/bin/env bash
# The house's size rules, checked on the source tree (not tests/, fuzz/, bench/, examples/):
#  - no module folder holds more than a quarter of the source lines;
#  - no header is over 400 lines;
#  - with Universal Ctags installed (`ctags --version`), no function is over 60 lines, but
#    the declarative tables scripts/long_tables.txt lists (option lists, key lists,
#    bindings: "<file pattern> <function> <reason>", a bash pattern for the file).
# Prints each folder's share and what breaks a rule; exits 1 when a rule is broken.
set -euo pipefail
cd "$(dirname "$0")/.."
status=0
# True when scripts/long_tables.txt lists the function (its file matching the pattern).
Exempt() {
  local pattern function reason
  while read -r pattern function reason; do
    [[ -z $pattern || $pattern == \#* ]] && continue
    # shellcheck disable=SC2053  # the pattern is a pattern
    [[ $1 == $pattern && $2 == $function ]] && return 0
  done <scripts/long_tables.txt
  return 1
}
mapfile -t files < <(git ls-files '*.h' '*.cc' | grep -vE '^(tests|fuzz|bench|examples)/')
total=$(cat "${files[@]}" | wc -l)
declare -A lines
for f in "${files[@]}"; do
  dir=${f%%/*}
  lines[$dir]=$((${lines[$dir]:-0} + $(wc -l <"$f")))
done
echo "source lines: $total"
for dir in $(printf '%s\n' "${!lines[@]}" | sort); do
  share=$((100 * ${lines[$dir]} / total))
  printf '  %-12s %6d  %3d %%\n' "$dir/" "${lines[$dir]}" "$share"
  if ((4 * ${lines[$dir]} > total)); then
    echo "FOLDER OVER A QUARTER: $dir/" >&2
    status=1
  fi
done
for f in "${files[@]}"; do
  if [[ $f == *.h ]] && (($(wc -l <"$f") > 400)); then
    echo "HEADER OVER 400 LINES: $f ($(wc -l <"$f"))" >&2
    status=1
  fi
done
if command -v ctags >/dev/null && ctags --version 2>/dev/null | grep -q Universal; then
  while read -r length file name; do
    if ! Exempt "${file#./}" "$name"; then
      echo "FUNCTION OVER 60 LINES: $file $name ($length)" >&2
      status=1
    fi
  done < <(ctags --c++-kinds=f --fields=+ne -o - "${files[@]}" 2>/dev/null |
    awk -F'\t' '{ line = ""; end = "";
      for (i = 4; i <= NF; i++) { if ($i ~ /^line:/) line = substr($i, 6); if ($i ~ /^end:/) end = substr($i, 5) }
      if (line != "" && end != "" && end - line + 1 > 60) print end - line + 1, $2, $1 }')
else
  echo "(no Universal Ctags: function lengths not checked)"
fi
exit $status
