#!/usr/bin/env bash
# Bad command lines get exit code 2 and a message naming what is wrong,
# before anything starts or connects (docs/reliability.md, gaps 3, 5, 6, 9).
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
# Durations that would overflow when converted to ns or tick counts (gap 6).
expect 2 "--seconds must be within \[0, 1e7\]" "$bin/hapsim-viewer" --session s --seconds 1e300
expect 2 "--connect-timeout-s must be within (0, 3600]" "$bin/hapsim-viewer" --session s --connect-timeout-s 1e16
expect 2 "--max-rate-hz must be within 0 or \[0.01, 1000\]" "$bin/hapsim-viewer" --session s --max-rate-hz 1e-12
expect 2 "--seconds must be within \[0, 1e7\]" "$bin/hapsim-bridge" --seconds 1e20
expect 2 "--seconds must be within \[0, 1e7\]" "$bin/hapsim-load" --seconds 1e20
expect 2 "hold time must be in \[0, 1e7\] s" "$bin/hapsim-bridge" --hold-s 1e300
# The same mistake gets the same exit code in the bridge and the load
# generator (gap 9): bad script, bad safety setting, bad session id, bad params.
expect 2 "speed must be in (0, 1\] m/s" "$bin/hapsim-bridge" --speed-mm-s 0
expect 2 "speed must be in (0, 1\] m/s" "$bin/hapsim-load" --speed-mm-s 0
expect 2 "force" "$bin/hapsim-bridge" --max-force-n -1
expect 2 "force" "$bin/hapsim-load" --max-force-n -1
expect 2 "--session must be within \[A-Za-z0-9_-\]{1,63}" "$bin/hapsim-bridge" --session "a b"
expect 2 "is not \[A-Za-z0-9_-\]{1,63}" "$bin/hapsim-load" --sessions "a b"
expect 2 "--params wants KEY=NUMBER" "$bin/hapsim-load" --create tissue_block --params stiffness
expect 2 "unknown backend 'phantom'" "$bin/hapsim-bridge" --backend phantom
echo "$failures failed"
[ "$failures" -eq 0 ]
