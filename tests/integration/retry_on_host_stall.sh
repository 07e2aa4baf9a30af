#!/usr/bin/env bash
# Runs an end-to-end test script (SCRIPT BIN_DIR WORK_DIR) and, only when it
# exits 75 — a check failed while the host itself was stalled (a bridge's
# or hapsim-load's servo that waited over ten periods for the CPU, or an
# instrument the check script found late: note_host_stall;
# checks.py's finish(), lib.sh's finish_checks) — runs it once more. A second failure of any kind
# fails the test; the first run's output stays in the log.
set -uo pipefail
script=${1:?usage: $0 SCRIPT BIN_DIR WORK_DIR}
shift
bash "$script" "$@"
rc=$?
if [ "$rc" -eq 75 ]; then
  echo "== $(basename "$script"): failed on a stalled host; running it once more"
  bash "$script" "$@"
  rc=$?
  [ "$rc" -eq 75 ] && rc=1
fi
exit "$rc"
