#!/usr/bin/env bash
# The knob table's outputs (include/masq/knobs.h; ctest: knob_docs): docs/knobs.md is what
# `masq info --env --markdown` writes, `masq info --env` lists every row with its value
# and names a bad one, and no file outside tests/ but knobs/knobs.cpp reads the
# environment itself. Usage: knob_docs.sh path/to/masq path/to/source
set -uo pipefail
masq=$1
src=$2
fail=0
if ! diff -u "$src/docs/knobs.md" <("$masq" info --env --markdown); then
  echo "FAIL: docs/knobs.md differs from the table; regenerate: masq info --env --markdown > docs/knobs.md"
  fail=1
fi
names=$(grep -oE '^\| `MASQ_[A-Z0-9_]+`' "$src/docs/knobs.md" | tr -d '|` ')
[ "$(wc -w <<<"$names")" -ge 30 ] || { echo "FAIL: docs/knobs.md lists $(wc -w <<<"$names") knobs"; fail=1; }
out=$(env -u MASQ_STEP_CHECK MASQ_CPU_THREADS=3 "$masq" info --env)
for name in $names; do
  grep -qE "^$name " <<<"$out" || { echo "FAIL: masq info --env does not list $name"; fail=1; }
done
grep -qE "^MASQ_CPU_THREADS +'3'$" <<<"$out" || { echo "FAIL: masq info --env does not show MASQ_CPU_THREADS='3'"; fail=1; }
grep -qE "^MASQ_STEP_CHECK +\(unset\)$" <<<"$out" || { echo "FAIL: masq info --env does not show MASQ_STEP_CHECK unset"; fail=1; }
if awk '/^    / && length > 100' <<<"$out" | grep -q .; then echo "FAIL: masq info --env wraps past 100 columns"; fail=1; fi
bad=$(MASQ_VK_WAIT_SECONDS=soon "$masq" info --env)
grep -q "bad: MASQ_VK_WAIT_SECONDS='soon' is not a positive integer" <<<"$bad" ||
  { echo "FAIL: masq info --env does not name the bad MASQ_VK_WAIT_SECONDS"; fail=1; }
if git -C "$src" rev-parse --git-dir >/dev/null 2>&1; then
  readers=$(git -C "$src" grep -l --untracked 'getenv(' -- ':!tests' ':!*.md')
  if [ "$readers" != "knobs/knobs.cpp" ]; then
    echo "FAIL: getenv outside knobs/knobs.cpp (read knobs through include/masq/knobs.h):"; echo "$readers"; fail=1
  fi
fi
[ "$fail" -eq 0 ] && echo "knob_docs: docs/knobs.md, masq info --env and the one reader agree with the table"
exit "$fail"
