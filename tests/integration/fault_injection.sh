#!/usr/bin/env bash
# Fault injection: two sessions, each driven by a synthetic
# device pressing into the tissue; session fb's bridge and viewer run
# throughout while session fa's bridge and viewer are killed with SIGKILL at
# random moments and restarted, three times each. After every event the
# server answers a health check and lists both sessions; at the end:
#  - fb's device never saw a model older than the watchdog's warning (20 ms),
#  - fa's last bridge re-owned its session (models received, fresh watchdog),
#  - fa's last viewer resynced (one keyframe, no gap) to the server's mesh,
#  - no device's rendered force exceeded the 2.5 N clamp,
#  - the server exits 0 on SIGTERM.
# Then the server itself is killed with SIGKILL and started again on its data
# directory, fa's last bridge still running: both sessions come back at the
# sim time their recordings reached (within 100 ms of where they were), fa's
# bridge drives fa again (fresh watchdog at the end), a new viewer resyncs to
# the restored mesh, and both sessions' recordings replay to every recorded
# state hash across the kill.
# Random moments come from FAULT_SEED (printed; default: random). Bounded:
# ~25 s, loopback only; every process is killed on exit.
set -euo pipefail
session=fa
source "$(dirname "$0")/lib.sh" "$@"
seed=${FAULT_SEED:-$RANDOM}
RANDOM=$seed
echo "fault injection seed $seed (FAULT_SEED=$seed reproduces the moments)"
# The server and session fb's clients on core 0, session fa's churning
# clients on core 1: process starts (library loading, DDS discovery) must not
# starve fb's bridge of CPU, which would age its models on the client side.
client_prefix=(); fb_prefix=()
if taskset -c 1 true 2>/dev/null; then server_prefix=(taskset -c 0); client_prefix=(taskset -c 1); fb_prefix=(taskset -c 0); fi
server_flags=("${every_tick_server[@]}" --data-dir data --record all)
start_server "fa:tissue_block,fb:tissue_block" "${server_flags[@]}"
ctl=("${client_prefix[@]}" timeout 20 "$bin/hapsim-ctl" --server "$addr" --timeout-s 10)
press=("${every_tick_client[@]}" --script insertion --start-height-mm 2 --depth-mm 3 --speed-mm-s 20 --hold-s 120 --dds-domain "$domain")
failures=0
fail() { echo "FAIL $*"; failures=$((failures + 1)); }
healthy() {  # after an event: the server answers and lists both sessions
  "${ctl[@]}" health >/dev/null || fail "health check after $1"
  "${ctl[@]}" list >list.txt || fail "list after $1"
  [ "$(grep -c '^f[ab] ' list.txt)" -eq 2 ] || fail "both sessions listed after $1"
}
random_sleep() { local ms=$(( $1 + RANDOM % $2 )); sleep "$(printf '%d.%03d' $((ms / 1000)) $((ms % 1000)))"; }

"${fb_prefix[@]}" "$bin/hapsim-bridge" --session fb --device-id 2 "${press[@]}" >fb_bridge.out 2>fb_bridge.log &
fb_bridge=$!; pids+=("$fb_bridge")
"${fb_prefix[@]}" "$bin/hapsim-viewer" --headless --server "$addr" --session fb --seconds 60 >fb_viewer.out 2>fb_viewer.log &
fb_viewer=$!; pids+=("$fb_viewer")

start_fa() {
  "${client_prefix[@]}" "$bin/hapsim-bridge" --session fa --device-id 1 "${press[@]}" >"fa_bridge$1.out" 2>"fa_bridge$1.log" &
  fa_bridge=$!; pids+=("$fa_bridge")
  "${client_prefix[@]}" "$bin/hapsim-viewer" --headless --server "$addr" --session fa --seconds 60 --obj "fa_viewer$1.obj" \
      >"fa_viewer$1.out" 2>"fa_viewer$1.log" &
  fa_viewer=$!; pids+=("$fa_viewer")
}
start_fa 0
for round in 1 2 3; do
  random_sleep 800 1200
  if (( RANDOM % 2 )); then
    kill -KILL "$fa_bridge"; wait "$fa_bridge" 2>/dev/null || true; healthy "killing fa's bridge (round $round)"
    random_sleep 100 600
    kill -KILL "$fa_viewer"; wait "$fa_viewer" 2>/dev/null || true; healthy "killing fa's viewer (round $round)"
  else
    kill -KILL "$fa_viewer"; wait "$fa_viewer" 2>/dev/null || true; healthy "killing fa's viewer (round $round)"
    random_sleep 100 600
    kill -KILL "$fa_bridge"; wait "$fa_bridge" 2>/dev/null || true; healthy "killing fa's bridge (round $round)"
  fi
  random_sleep 100 500
  start_fa "$round"
  healthy "restarting fa's bridge and viewer (round $round)"
done
sleep 2.0  # the last bridge presses and holds; the last viewer follows
"${ctl[@]}" snapshot fa --obj server_fa.obj >/dev/null || fail "snapshot of fa"
stop_process fa_viewer_rc "$fa_viewer"
stop_process fb_bridge_rc "$fb_bridge"
stop_process fb_viewer_rc "$fb_viewer"

# The server killed mid-session and started again on its data directory;
# fa's bridge keeps streaming through it.
"${ctl[@]}" info fa >fa_before_kill.txt || fail "info fa before the server kill"
"${ctl[@]}" info fb >fb_before_kill.txt || fail "info fb before the server kill"
kill -KILL "$server"; wait "$server" 2>/dev/null || true
mv server.log server_killed.log
random_sleep 200 500
start_server "" "${server_flags[@]}"
ctl=("${client_prefix[@]}" timeout 20 "$bin/hapsim-ctl" --server "$addr" --timeout-s 10)
healthy "killing and restarting the server"
grep -q "brought back 2 of 2 sessions" server.log || fail "the restarted server did not bring back fa and fb"
sim_of() { sed -n 's/.*sim_time_s=\([0-9.]*\).*/\1/p' "$1"; }
"${ctl[@]}" info fb >fb_after_kill.txt || fail "info fb after the restart"
awk -v a="$(sim_of fb_before_kill.txt)" -v b="$(sim_of fb_after_kill.txt)" 'BEGIN { exit !(b >= a - 0.1) }' ||
  fail "fb came back at sim time $(sim_of fb_after_kill.txt) s, before $(sim_of fb_before_kill.txt) s less 100 ms"
"${client_prefix[@]}" "$bin/hapsim-viewer" --headless --server "$addr" --session fa --seconds 60 --obj fa_viewer4.obj \
    >fa_viewer4.out 2>fa_viewer4.log &
fa_viewer=$!; pids+=("$fa_viewer")
sleep 2.0  # fa's bridge presses again; the new viewer follows
"${ctl[@]}" snapshot fa --obj server_fa4.obj >/dev/null || fail "snapshot of fa after the restart"
stop_process fa_bridge_rc "$fa_bridge"
stop_process fa_viewer4_rc "$fa_viewer"
stop_process server_rc "$server"
pids=()
for f in data/recordings/*/*.hrec; do
  "$bin/hapsim-replay" "$f" >"replay_$(basename "$f").txt" || fail "$f does not replay to its hashes"
done
[ "$(grep -l 'restarted 1 time' replay_*.txt | wc -l)" -eq 2 ] || fail "fa's and fb's recordings do not both span the kill"
echo "exit codes: server $server_rc, fa bridge $fa_bridge_rc, fa viewer $fa_viewer_rc, fb bridge $fb_bridge_rc, fb viewer $fb_viewer_rc, fa viewer after the restart $fa_viewer4_rc"
cat fb_bridge.out fa_bridge3.out fa_viewer3.out fa_viewer4.out replay_*.txt
[ "$server_rc" -eq 0 ] || fail "server exit code $server_rc"
for rc in "$fa_bridge_rc" "$fa_viewer_rc" "$fb_bridge_rc" "$fb_viewer_rc" "$fa_viewer4_rc"; do [ "$rc" -eq 0 ] || fail "a client exited $rc"; done
field() { sed -n "s|.*$1.*|\\1|p" "$2" | head -n1; }
# fb: never a stale model, never above the clamp.
fb_age_max=$(field 'model age p50 [0-9.]* / p99 [0-9.]* / max \([0-9.]*\) ms' fb_bridge.out)
fb_warnings=$(field 'watchdog [a-z]* (warnings \([0-9]*\),' fb_bridge.out)
awk -v a="$fb_age_max" 'BEGIN { exit !(a != "" && a <= 20.0) }' || fail "fb's model age max ${fb_age_max} ms > 20 ms"
[ "$fb_warnings" = 0 ] || fail "fb's watchdog warned ${fb_warnings} times"
# fa's last bridge re-owned its session.
fa_models=$(field 'force models received \([0-9]*\)' fa_bridge3.out)
[ "${fa_models:-0}" -gt 1000 ] || fail "fa's restarted bridge received ${fa_models:-0} models"
grep -q 'watchdog fresh' fa_bridge3.out || fail "fa's restarted bridge's watchdog is not fresh at the end"
for f in fb_bridge.out fa_bridge*.out; do
  peak=$(field 'force peak \([0-9.]*\) N' "$f")
  [ -z "$peak" ] || awk -v p="$peak" 'BEGIN { exit !(p <= 2.5) }' || fail "$f: rendered force peak $peak N above the clamp"
done
# fa's last viewer resynced from one keyframe, with no gap, to the server's mesh.
grep -q 'keyframes 1, ' fa_viewer3.out || fail "fa's restarted viewer did not start from exactly one keyframe"
grep -q 'gaps 0, topology mismatches 0, malformed 0' fa_viewer3.out || fail "fa's restarted viewer saw gaps or bad frames"
[ "$(grep -c '^v ' fa_viewer3.obj)" -eq "$(grep -c '^v ' server_fa.obj)" ] &&
  [ "$(grep -c '^f ' fa_viewer3.obj)" -eq "$(grep -c '^f ' server_fa.obj)" ] || fail "fa's viewer mesh differs from the server's"
# After the server's restart: a new viewer resynced to the restored session.
grep -q 'keyframes 1, ' fa_viewer4.out || fail "fa's viewer after the restart did not start from exactly one keyframe"
grep -q 'gaps 0, topology mismatches 0, malformed 0' fa_viewer4.out || fail "fa's viewer after the restart saw gaps"
[ "$(grep -c '^v ' fa_viewer4.obj)" -eq "$(grep -c '^v ' server_fa4.obj)" ] &&
  [ "$(grep -c '^f ' fa_viewer4.obj)" -eq "$(grep -c '^f ' server_fa4.obj)" ] || fail "fa's viewer mesh after the restart differs"
echo "$failures failed"
finish_checks "$failures"
