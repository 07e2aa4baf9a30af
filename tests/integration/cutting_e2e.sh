#!/usr/bin/env bash
# Cutting end to end: a `cutting` session driven by the synthetic bridge's
# `cut` script (approach, press 1.5 mm in, a 12 mm stroke along +x at 5 mm/s,
# lift), watched by two headless viewers, one of them joining mid-cut.
# check_cutting_e2e.py checks that the viewers followed the cut as topology
# deltas (one keyframe each, no resubscribe), that their final meshes agree
# and hold a wound, that cut_start/cut_end came with the incision length,
# and that the bridge's force trace has the blade's drag while cutting and
# nothing in the air.
set -euo pipefail
session=cut
source "$(dirname "$0")/lib.sh" "$@"
start_server "$session:cutting"

"$bin/hapsim-viewer" --headless --server "$addr" --session "$session" --seconds 60 --obj early.obj >early.out 2>early.log &
early=$!; pids+=("$early")
sleep 0.3
# 5 mm above the skin at x = -6 mm; 1 + 0.3 + 2.4 + 1.3 s = 5 s. Ends by itself.
"$bin/hapsim-bridge" --session "$session" --dds-domain "$domain" --script cut \
    --start-height-mm 5 --depth-mm 1.5 --speed-mm-s 5 --entry-x-mm -6 --cut-length-mm 12 \
    --trace trace.csv >bridge.out 2>bridge.log &
bridge=$!; pids+=("$bridge")
sleep 2.5  # mid-stroke: the late viewer starts from a keyframe of a half-cut mesh
"$bin/hapsim-viewer" --headless --server "$addr" --session "$session" --seconds 60 --obj late.obj >late.out 2>late.log &
late=$!; pids+=("$late")
wait "$bridge" && bridge_rc=0 || bridge_rc=$?
sleep 1.0  # the wound settles a little; both viewers catch the last frames
stop_process early_rc "$early"
stop_process late_rc "$late"
stop_process server_rc "$server"
pids=()
echo "exit codes: server $server_rc, bridge $bridge_rc, viewers $early_rc $late_rc"
cat bridge.out early.out late.out server.out
[ "$server_rc" -eq 0 ] && [ "$bridge_rc" -eq 0 ] && [ "$early_rc" -eq 0 ] && [ "$late_rc" -eq 0 ]
/usr/bin/python3 "$here/check_cutting_e2e.py" "$work"
