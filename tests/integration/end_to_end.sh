#!/usr/bin/env bash
# End-to-end test: hapsim-server + hapsim-bridge (synthetic insertion) +
# hapsim-viewer (headless) on loopback. Checks, via check_end_to_end.py:
#  - the bridge received force models whose echoed pose seq advances;
#  - contact force is nonzero while pressing and ~0 once withdrawn;
#  - the viewer's final mesh equals the server's snapshot within the
#    quantisation step, after an injected frame loss forced a resync;
#  - every process exits 0 on SIGTERM.
# Bounded: every wait has a time limit; nothing leaves 127.0.0.1.
set -euo pipefail
session=e2e
source "$(dirname "$0")/lib.sh" "$@"
start_server "$session"

"$bin/hapsim-viewer" --headless --server "$addr" --session "$session" --seconds 60 --obj viewer.obj \
    --debug-drop-seq 20 --name e2e-viewer >viewer.out 2>viewer.log &
viewer=$!; pids+=("$viewer")

# Two insertion cycles (5 mm above -> 4 mm deep -> back), then SIGTERM.
"$bin/hapsim-bridge" --session "$session" --dds-domain "$domain" --script insertion \
    --start-height-mm 5 --depth-mm 4 --speed-mm-s 20 --hold-s 0.3 --trace trace.csv >bridge.out 2>bridge.log &
bridge=$!; pids+=("$bridge")
sleep 3.2
stop_process bridge_rc "$bridge"

# A second device run holds the needle 4 mm deep; freeze the session there
# and take the server's full-precision copy of the deformed mesh.
"$bin/hapsim-bridge" --session "$session" --dds-domain "$domain" --script insertion \
    --start-height-mm 5 --depth-mm 4 --speed-mm-s 20 --hold-s 30 >bridge2.out 2>bridge2.log &
bridge2=$!; pids+=("$bridge2")
sleep 1.2
"$bin/hapsim-ctl" --server "$addr" pause "$session" >ctl.out
sleep 0.5
"$bin/hapsim-ctl" --server "$addr" snapshot "$session" --obj server.obj >>ctl.out
"$bin/hapsim-ctl" --server "$addr" info "$session" >>ctl.out
sleep 0.3
kill -TERM "$bridge2"
wait "$bridge2" || true

stop_process viewer_rc "$viewer"
stop_process server_rc "$server"
pids=()

echo "exit codes: server $server_rc, bridge $bridge_rc, viewer $viewer_rc"
cat bridge.out viewer.out server.out ctl.out
/usr/bin/python3 "$here/check_end_to_end.py" "$work" "$server_rc" "$bridge_rc" "$viewer_rc"
