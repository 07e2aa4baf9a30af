#!/usr/bin/env bash
# Bad command lines get exit code 2 and a message naming what is wrong,
# before anything starts or connects (docs/reliability.md, gaps 3 and 5).
# Usage: flag_errors.sh BIN_DIR
set -uo pipefail
bin=${1:?usage: $0 BIN_DIR}
failures=0
# expect CODE PATTERN COMMAND...: exit code CODE and stderr matching PATTERN.
expect() {
  local code=$1 pattern=$2; shift 2
  local err rc
  err=$("$@" 2>&1 >/dev/null); rc=$?
  if [ "$rc" -eq "$code" ] && grep -q -- "$pattern" <<<"$err"; then
    echo "ok   $* -> $rc: $(head -1 <<<"$err")"
  else
    echo "FAIL $* -> exit $rc (want $code), stderr: $err"; failures=$((failures + 1))
  fi
}
expect 2 "create does not take option '--scen'" "$bin/hapsim-ctl" --server 127.0.0.1:9 create --scen cutting
expect 2 "list does not take option '--id'" "$bin/hapsim-ctl" --server 127.0.0.1:9 list --id x
expect 2 "option '--obj' needs a value" "$bin/hapsim-ctl" --server 127.0.0.1:9 snapshot s1 --obj
expect 2 "--frame-rate-hz must be within (0, 1000]" "$bin/hapsim-server" --listen 127.0.0.1:0 --frame-rate-hz 0
expect 2 "--pose-timeout-ms must be within (0, 60000]" "$bin/hapsim-server" --listen 127.0.0.1:0 --pose-timeout-ms 1e18
expect 2 "--quantum-mm must be within (0, 1]" "$bin/hapsim-server" --listen 127.0.0.1:0 --quantum-mm 5
echo "$failures failed"
[ "$failures" -eq 0 ]
