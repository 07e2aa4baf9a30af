#!/usr/bin/env bash
# One DDS partition per session, with one hapsim-bridge process per
# device (the classroom topology). Two sessions, two bridges: each bridge
# receives its own session's models and none of the other's; then session A
# is closed while its bridge keeps publishing: that bridge gets nothing back
# and its watchdog fades and disarms, while B's bridge carries on; a bridge
# for a session nobody serves is told so. check_partitions.py reads the output.
set -euo pipefail
source "$(dirname "$0")/lib.sh" "$@"
start_server "room-a,room-b" "${every_tick_server[@]}"

bridge() {  # bridge NAME SESSION DEVICE_ID SECONDS
  "$bin/hapsim-bridge" --session "$2" --device-id "$3" --dds-domain "$domain" "${every_tick_client[@]}" --script constant_speed \
      --keep-running --seconds "$4" --trace "$1.csv" >"$1.out" 2>"$1.log" &
  pids+=("$!")
}
bridge a room-a 11 4
bridge_a=${pids[-1]}
bridge b room-b 12 4
bridge_b=${pids[-1]}
sleep 2.0
"$bin/hapsim-ctl" --server "$addr" close room-a >close.out 2>&1
"$bin/hapsim-bridge" --session nobody-here --device-id 13 --dds-domain "$domain" --script hold --seconds 1 \
    >ghost.out 2>ghost.log
wait "$bridge_a" "$bridge_b"
"$bin/hapsim-ctl" --server "$addr" list >sessions.txt
stop_process server_rc "$server"
pids=()
cat a.out b.out sessions.txt
/usr/bin/python3 "$here/check_partitions.py" "$work"
