#!/usr/bin/env bash
# One hapsim-bridge with two devices (--device twice: one servo thread each,
# one DDS participant) driving two sessions of one server. Each device must
# get its own session's models only, and each session must be clocked by
# its own device. check_two_devices.py reads the outputs.
set -euo pipefail
source "$(dirname "$0")/lib.sh" "$@"
start_server "t1:tissue_block,t2:tissue_block" "${every_tick_server[@]}"
"$bin/hapsim-bridge" --device t1 --device t2 --device-id 5 --dds-domain "$domain" "${every_tick_client[@]}" --script insertion \
    --depth-mm 5 --seconds 2 >bridge.out 2>bridge.log
stop_process server_rc "$server"
pids=()
[ "$server_rc" = 0 ] || { echo "server exited with $server_rc"; cat server.log; exit 1; }
cat bridge.out server.out
/usr/bin/python3 "$here/check_two_devices.py" "$work"
