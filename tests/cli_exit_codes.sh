#!/usr/bin/env bash
# The CLI's documented exit codes and per-subcommand examples (ctest: cli_exit_codes).
# Usage: cli_exit_codes.sh path/to/masq
set -uo pipefail
masq=$1
fail=0
expect() { # expect CODE ARGS...: run masq ARGS, check its exit code
  local want=$1; shift
  "$masq" "$@" >/tmp/masq_cli_out.$$ 2>&1
  local got=$?
  if [ "$got" -ne "$want" ]; then
    echo "FAIL: masq $* exited $got, expected $want"; sed 's/^/  | /' /tmp/masq_cli_out.$$ | tail -5; fail=1
  fi
}
expect 0 --help
for sub in info render bench stress report; do
  expect 0 "$sub" --help
  # Captured first: `masq ... | grep -q` under pipefail fails when grep stops reading early.
  help=$("$masq" "$sub" --help)
  if ! grep -q '^Examples:' <<<"$help"; then echo "FAIL: masq $sub --help shows no examples"; fail=1; fi
done
help=$("$masq" --help)
grep -q 'Exit codes' <<<"$help" || { echo "FAIL: masq --help does not document exit codes"; fail=1; }
expect 2                                   # no subcommand
expect 2 frobnicate
expect 2 bench --backend nope
expect 2 render --method nope
expect 2 bench --builder nope
expect 2 render --builder sah,spatial
expect 2 bench --nodes w16
expect 1 bench --nodes w4,w4 --backend cpu                                   # repeated format
expect 1 render --backend cpu --nodes w4,q8 --out /tmp/masq_cli_exit         # render takes one
expect 2 stress --rays 1
expect 2 render --width 0
expect 1 render --backend cpu --file /nonexistent/scene.obj --out /tmp/masq_cli_exit
expect 1 render --backend cpu --file "$0" --out /tmp/masq_cli_exit   # unknown extension .sh
# An explicit device selector that names nothing: exit 1, one line naming it (docs/devices.md).
MASQ_VK_DEVICE=no-such-gpu expect 1 bench --backend vulkan --width 8 --height 8
if [ "$(wc -l </tmp/masq_cli_out.$$)" -ne 1 ] || ! grep -q "MASQ_VK_DEVICE='no-such-gpu' matches no Vulkan device" /tmp/masq_cli_out.$$; then
  echo "FAIL: MASQ_VK_DEVICE=no-such-gpu: not one line naming it"; sed 's/^/  | /' /tmp/masq_cli_out.$$ | tail -5; fail=1
fi
MASQ_CL_DEVICE=no-such-gpu expect 1 stress --quick --backend opencl
expect 1 render --backend vulkan --device no-such-gpu --out /tmp/masq_cli_exit
expect 2 bench --device metal=0
# masq report: a bad input file stops it with one line naming the file (docs/bench.md, "masq report").
expect 2 report                                                              # no results file
expect 1 report /nonexistent/results.json --out /tmp/masq_cli_exit
if [ "$(wc -l </tmp/masq_cli_out.$$)" -ne 1 ] || ! grep -q "^masq: /nonexistent/results.json: " /tmp/masq_cli_out.$$; then
  echo "FAIL: masq report of a missing file: not one line naming it"; sed 's/^/  | /' /tmp/masq_cli_out.$$ | tail -5; fail=1
fi
echo '{"machine": {}}' >/tmp/masq_cli_report.$$.json
expect 1 report /tmp/masq_cli_report.$$.json --out /tmp/masq_cli_exit
if [ "$(wc -l </tmp/masq_cli_out.$$)" -ne 1 ] || ! grep -q "^masq: /tmp/masq_cli_report.$$.json: not a masq results file" /tmp/masq_cli_out.$$; then
  echo "FAIL: masq report of a non-results JSON file: not one line naming it"; sed 's/^/  | /' /tmp/masq_cli_out.$$ | tail -5; fail=1
fi
rm -f /tmp/masq_cli_report.$$.json
rm -f /tmp/masq_cli_out.$$
[ $fail -eq 0 ] && echo "cli exit codes: ok"
exit $fail
