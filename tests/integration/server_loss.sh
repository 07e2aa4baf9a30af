#!/usr/bin/env bash
# Safety fault test: the physics server dies (SIGKILL) while the device is
# pressing into the tissue. The bridge's watchdog must take the force to
# zero within its disarm age (100 ms) and keep it there; the bridge itself
# keeps running and exits 0 on SIGTERM. check_server_loss.py reads the trace.
set -euo pipefail
session=loss
source "$(dirname "$0")/lib.sh" "$@"
start_server "$session"

# Press 4 mm into the block and hold there for 30 s.
"$bin/hapsim-bridge" --session "$session" --dds-domain "$domain" --script insertion \
    --start-height-mm 2 --depth-mm 4 --speed-mm-s 20 --hold-s 30 --trace trace.csv >bridge.out 2>bridge.log &
bridge=$!; pids+=("$bridge")
sleep 1.0
kill -KILL "$server"
wait "$server" 2>/dev/null || true
sleep 0.6
stop_process bridge_rc "$bridge"
pids=()
cat bridge.out
[ "$bridge_rc" -eq 0 ] || { echo "bridge exited $bridge_rc"; exit 1; }
/usr/bin/python3 "$here/check_server_loss.py" "$work"
