#!/usr/bin/env bash
# hapsim-load against a hapsim-server on loopback: 16 devices on 16 sessions
# it creates, then bad input — sessions that cannot be created, a load
# generator killed mid-run. check_load_sessions.py checks:
#  - every device received models with advancing echoed seqs, no regression,
#    no watchdog disarm; the server reports late_ticks for all 16 sessions;
#  - a creation failure exits non-zero with the server's error and leaves
#    no session behind; sessions are closed at exit unless --keep-sessions;
#  - after a SIGKILL the server stays healthy and the killed generator's
#    sessions report device_streaming=0 once the pose timeout has passed.
# Bounded: every run has a time limit; nothing leaves 127.0.0.1.
set -euo pipefail
source "$(dirname "$0")/lib.sh" "$@"
start_server "" --pose-timeout-ms 250 "${every_tick_server[@]}"
load=("$bin/hapsim-load" --server "$addr" --dds-domain "$domain" "${every_tick_client[@]}")
ctl=("$bin/hapsim-ctl" --server "$addr")
# run NAME COMMAND...: stdout to NAME.out, stderr to NAME.err, exit code to NAME.rc
run() { local name=$1 code=0; shift; "$@" >"$name.out" 2>"$name.err" || code=$?; echo "$code" >"$name.rc"; }

# 1. The classroom: 16 devices, 4 s, sessions kept for the listing below.
run load "${load[@]}" --create tissue_block --devices 16 --seconds 4 --keep-sessions --json load.json --csv load.csv
"${ctl[@]}" list >list.txt

# 2. Creation failures: an id that exists, a scene that does not, and a list
#    whose second session exists (the first must be closed again).
run dup "${load[@]}" --create tissue_block --devices 1 --seconds 1
run scene "${load[@]}" --create no_such_scene --session-prefix nosuch- --devices 1 --seconds 1
run partial "${load[@]}" --create tissue_block --sessions fresh-a,load-3 --seconds 1
"${ctl[@]}" list >after_failures.txt

# 3. A load generator killed mid-run.
"${load[@]}" --create tissue_block --devices 4 --session-prefix killed- --first-device-id 2000 --seconds 30 \
    >killed.out 2>killed.err &
killed=$!; pids+=("$killed")
for _ in $(seq 1 50); do
  "${ctl[@]}" list >alive.txt
  [ "$(grep -c '^killed-.* device_streaming=1' alive.txt || true)" -eq 4 ] && break
  sleep 0.1
done
sleep 0.3
"${ctl[@]}" list >alive.txt
kill -KILL "$killed"
wait "$killed" 2>/dev/null || true
sleep 0.8  # > the 250 ms pose timeout
run health "${ctl[@]}" health
"${ctl[@]}" list >after_kill.txt

# 4. Without --keep-sessions the sessions are closed at exit.
run closed "${load[@]}" --create tissue_block --devices 2 --session-prefix closed- --seconds 0.5
"${ctl[@]}" list >after_close.txt

stop_process server_rc "$server"
pids=()
cat load.out dup.err scene.err partial.err
/usr/bin/python3 "$here/check_load_sessions.py" "$work" "$server_rc"
