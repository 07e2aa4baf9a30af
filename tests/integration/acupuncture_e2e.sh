#!/usr/bin/env bash
# Acupuncture end to end: an `acupuncture` session driven by the synthetic
# bridge's constant-speed insertion through skin, fat and muscle and out
# again, watched by a headless viewer. check_acupuncture_e2e.py checks that
# the three punctures appear in order in the viewer's frames and as force
# drops at the same depths in the bridge's force trace.
set -euo pipefail
session=acu
source "$(dirname "$0")/lib.sh" "$@"
start_server "$session:acupuncture"

"$bin/hapsim-viewer" --headless --server "$addr" --session "$session" --seconds 60 --obj viewer.obj >viewer.out 2>viewer.log &
viewer=$!; pids+=("$viewer")
sleep 0.3
# 1 mm above the skin, 5 mm/s down to 14 mm (skin pierced ~2.6 mm deep, the
# fat ~1.1 mm below that, the muscle ~2.9 mm below its top at 9.2 mm) and
# back out: 6 s. The script ends by itself. Every layer's contact now lasts
# over 200 ticks at this speed; with the earlier linear force net it was 5
# ticks for the fat.
"$bin/hapsim-bridge" --session "$session" --dds-domain "$domain" --script constant_speed \
    --start-height-mm 1 --depth-mm 14 --speed-mm-s 5 --trace trace.csv >bridge.out 2>bridge.log &
bridge=$!; pids+=("$bridge")
wait "$bridge" && bridge_rc=0 || bridge_rc=$?
sleep 0.5
stop_process viewer_rc "$viewer"
stop_process server_rc "$server"
pids=()
echo "exit codes: server $server_rc, bridge $bridge_rc, viewer $viewer_rc"
cat bridge.out viewer.out server.out
[ "$server_rc" -eq 0 ] && [ "$bridge_rc" -eq 0 ] && [ "$viewer_rc" -eq 0 ]
/usr/bin/python3 "$here/check_acupuncture_e2e.py" "$work"
