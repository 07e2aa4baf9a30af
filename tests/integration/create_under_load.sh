#!/usr/bin/env bash
# Creating the most expensive accepted sessions while a classroom runs
# (the target: "creating a session of any accepted parameters while 32 others
# run: no device's model age exceeds 20 ms"). hapsim-load creates and drives
# DEVICES tissue_block sessions; 2 s in (all streaming), hapsim-ctl creates
# (docs/scene-limits.md):
#  - acupuncture at every limit, the slowest accepted build (~0.6 s) and step,
#  - tissue_block at the step-cost limit (midpoint averaging, 69 x 69),
#  - tissue_block at the largest grid (101 x 101, the largest tissue build),
# then asks for shf_lmax=30, which must be refused with INVALID_ARGUMENT
# naming the parameter. Each created session is checked to tick and closed
# again; 2 s after the last, the load is stopped (SIGINT: it still writes
# its report). check_create_under_load.py checks the load JSON
# (every device: model age max <= 20 ms, no watchdog warning/fade/disarm),
# that each creation succeeded while the load was running, and the refusal.
# Timing-sensitive: registered RUN_SERIAL, and like tests/bench/capacity.sh
# the server runs pinned to core 0 and every client to core 1, so the load
# generator's own scheduling does not land inside the server's figures (on a
# 2-core machine a saturated, unpinned pair measured 20+ ms model ages that
# were the clients' delays). The builds run at nice 10 beside the busy
# sessions, so on a slow machine they take seconds: hapsim-ctl waits 30 s.
#
# DEVICES (environment, default 24): the target's 32 was measured on a machine where
# a tissue_block session-tick cost 18 µs of server CPU (32 sessions: 60 % of
# core 0). The CI machines measured 25 µs (AMD EPYC VM): 32
# sessions alone fill ~80 % of the core, the build's own CPU tips it into
# overload (late ticks 15 %) and the builds starve for 30 s — a capacity
# limit, not a creation stall, which is what this test guards. 24 sessions
# leave the same headroom there that 32 left on the first; DEVICES=32 reproduces
# the target's figure on a machine that fast (docs/performance.md, Capacity).
# A slower host (a PVM guest measured 30-45 µs) is filled by 24 too, so the
# class's share of core 0 is measured once it streams (the server's
# utime+stime over 1 s): above MAX_CLASS_SHARE (0.6) the load restarts (at
# most twice) with the devices that fill FIT_CLASS_SHARE (0.5) of the core, at
# least 8.
# Both shares and the device count go to times.txt and the log.
# Bounded: every client runs under `timeout`, the whole script takes
# ~10-20 s; nothing leaves 127.0.0.1.
set -euo pipefail
source "$(dirname "$0")/lib.sh" "$@"
# `timeout` runs its command in its own process group: kill the group too.
cleanup() { for p in "${pids[@]}"; do kill -KILL -- "-$p" "$p" 2>/dev/null || true; done; }
devices=${DEVICES:-24}
client_prefix=()
if taskset -c 1 true 2>/dev/null; then server_prefix=(taskset -c 0); client_prefix=(taskset -c 1); fi
start_server "" --max-sessions 64 "${every_tick_server[@]}"
# The control calls at nice 10: a hapsim-ctl starting on the client core
# must not preempt the measured devices' servo and receive threads.
ctl=("${client_prefix[@]}" nice -n 10 timeout 40 "$bin/hapsim-ctl" --server "$addr" --timeout-s 30)
now() { date +%s.%N; }

acupuncture_worst=(--param shf_lmax=16 --param shf_samples=3000 --param patch_grid_nodes=101
  --param skin_rings=30 --param fat_rings=30 --param muscle_rings=30
  --param skin_spacing_m=0.01 --param fat_spacing_m=0.01 --param muscle_spacing_m=0.01
  --param patch_size_m=0.2 --param springback_eta_rate_per_step=0
  --param skin_puncture_force_N=2.5 --param fat_puncture_force_N=2.5 --param muscle_puncture_force_N=2.5)

# The class: hapsim-load creating and driving $1 tissue_block sessions.
start_load() {
  devices=$1
  echo "load_start $(now)" >times.txt
  echo "devices $devices" >>times.txt
  "${client_prefix[@]}" timeout 90 "$bin/hapsim-load" --server "$addr" --dds-domain "$domain" "${every_tick_client[@]}" \
      --create tissue_block --devices "$devices" --seconds 60 --json load.json --csv load.csv --interval-s 0.1 \
      --intervals-csv intervals.csv >load.out 2>load.err &
  load=$!; pids+=("$load")
}

# Wait until the devices stream (at most 10 s), then measure the class's
# share of the server's core over 1 s.
wait_streaming_and_measure() {
  for _ in $(seq 1 100); do
    "${ctl[@]}" list >streaming.txt 2>/dev/null || true
    [ "$(grep -c '^load-.* device_streaming=1' streaming.txt || true)" -eq "$devices" ] && break
    sleep 0.1
  done
  local cpu0 t0
  cpu0=$(server_cpu_s) t0=$(now)
  sleep 1
  class_share=$(awk -v c0="$cpu0" -v c1="$(server_cpu_s)" -v t0="$t0" -v t1="$(now)" \
      'BEGIN { printf "%.3f", (c1 - c0) / (t1 - t0) }')
}
server_cpu_s() { awk -v hz="$(getconf CLK_TCK)" '{ print ($14 + $15) / hz }' "/proc/$server/stat"; }

MAX_CLASS_SHARE=0.6 FIT_CLASS_SHARE=0.5
start_load "$devices"
wait_streaming_and_measure
echo "class share of core 0 with $devices devices: $class_share"
# At most two restarts: a session's cost does not scale exactly with their number.
for _ in 1 2; do
  awk -v s="$class_share" -v max="$MAX_CLASS_SHARE" -v n="$devices" 'BEGIN { exit !(s > max && n > 8) }' || break
  fitted=$(awk -v s="$class_share" -v n="$devices" -v fit="$FIT_CLASS_SHARE" \
      'BEGIN { d = int(n * fit / s); print (d < 8 ? 8 : d) }')
  echo "over $MAX_CLASS_SHARE of the core: a capacity limit here; restarting the load with $fitted devices"
  kill -INT "$load"; wait "$load" || true
  start_load "$fitted"
  wait_streaming_and_measure
  echo "class share of core 0 with $devices devices: $class_share"
done
echo "class_share $class_share" >>times.txt

# Creations begin once the load has run for 2 s.
sleep "$(awk -v t0="$(head -1 times.txt | cut -d' ' -f2)" -v now="$(now)" \
    'BEGIN { d = t0 + 2 - now; printf "%.3f", (d > 0.2 ? d : 0.2) }')"
echo "streaming $(grep -c '^load-.* device_streaming=1' streaming.txt || true)" >>times.txt

# create NAME CTL-ARGS...: NAME.out/.err/.rc, start and end times in times.txt.
# A created session is a probe, not load: its info (it ticks) goes to
# NAME.info and it is closed at once, so the load's core is not left
# overloaded by the worst step costs after the creation under test.
create() {
  local name=$1 code=0; shift
  echo "${name}_start $(now)" >>times.txt
  "${ctl[@]}" create "$@" >"$name.out" 2>"$name.err" || code=$?
  echo "${name}_end $(now)" >>times.txt
  echo "$code" >"$name.rc"
  local id
  id=$(awk 'NR == 1 { print $1 }' "$name.out")
  if [ "$code" -eq 0 ] && [ -n "$id" ]; then
    sleep 0.05
    "${ctl[@]}" info "$id" >"$name.info" 2>&1 || true
    "${ctl[@]}" close "$id" >/dev/null 2>&1 || true
  fi
}
create acupuncture --id worst-acupuncture --scene acupuncture "${acupuncture_worst[@]}"
create tissue_cost --id worst-tissue-cost --scene tissue_block --param integrator=3 --param grid_nodes=69
create tissue_grid --id worst-tissue-grid --scene tissue_block --param grid_nodes=101
create refused --id too-deep --scene acupuncture --param shf_lmax=30
kill -0 "$load" 2>/dev/null && echo "load_running_after_creations 1" >>times.txt
"${ctl[@]}" list >during.txt || true
sleep 2
kill -INT "$load" 2>/dev/null || true

load_rc=0
wait "$load" || load_rc=$?
echo "load_end $(now)" >>times.txt
echo "$load_rc" >load.rc
"${ctl[@]}" list >after.txt || true
stop_process server_rc "$server"
pids=()
cat load.out
/usr/bin/python3 "$here/check_create_under_load.py" "$work" "$server_rc"
