#!/usr/bin/env bash
# Capacity benchmark (not in CI, run by hand on a quiet
# machine). For every MODE x SCENE x N: a hapsim-server pinned to core 0
# with N sessions created first (hapsim-ctl create), driven for RUN_S seconds
# from core 1 by
#   load     one hapsim-load process (N devices, one DDS participant), or
#   bridges  N hapsim-bridge processes (one participant per device, the
#            classroom topology; launches spread over ~1 s like hapsim-load's
#            default script phases),
# with the server's CPU time (/proc/PID/stat utime+stime), the host's UDP
# counters (/proc/net/snmp), `hapsim-ctl list` and — this build's server
# only, from its metrics endpoint (--metrics-listen on its own address, port
# 0) — every session's tick work read before and after the drive. With BASELINE_BIN the older server in that directory runs right
# after the current one with the same load and the same clients. Cyclone's
# ddsperf ping/pong at 1 kHz (pong on core 0, ping on core 1) runs first as
# the transport baseline. Prints one markdown table (capacity_table.py) and
# keeps every raw output under OUT_DIR.
#
#   tests/bench/capacity.sh [BIN_DIR] [OUT_DIR]
#
#   BIN_DIR  hapsim binaries (default: build/bin)
#   OUT_DIR  results (default: build/capacity-<UTC time>); table in capacity.md,
#            per-run figures in capacity.csv, raw outputs in runs/
#
# Environment (defaults in brackets):
#   COUNTS [1 8 16 32 64]            sessions per run (at most 64)
#   SCENES [tissue_block acupuncture]
#   MODES [load bridges]
#   RUN_S [20]                       seconds each client drives its device
#   SCRIPT [insertion]               synthetic script of every device
#   SCENE_PARAMS []                  scene parameters of every session, as
#                                    KEY=NUMBER words (hapsim-ctl create
#                                    --param), e.g. "rest_force_N=0"
#   BASELINE_BIN []                  directory with an older hapsim-server
#                                    (e.g. a build from before the worker pool:
#                                    one thread per session)
#   BASELINE_CLIENT_BIN [BASELINE_BIN if it holds a hapsim-bridge, else BIN_DIR]
#                                    clients run against the baseline server
#                                    (hapsim-bridge, hapsim-load; a client
#                                    missing there comes from BIN_DIR). Before
#                                    the series, each mode's client gets a 1 s
#                                    probe against the baseline server; if it
#                                    receives no force model (a DDS protocol
#                                    change, e.g. per-session partitions) that
#                                    mode's baseline runs are skipped.
#   DDSPERF_S [10]                   ddsperf ping duration (0: skip)
#   CODINGS [every]                  what the devices and the server send, one
#                                    series each: `every` (a pose and a model
#                                    every tick: --pose-deadband-mm 0 and
#                                    --model-deadband 0, as the earlier
#                                    figures) or `deadband` (the shipped
#                                    defaults: perceptual deadband coding)
#   LOAD_CLOCKS [own]                hapsim-load's device clocks: `own` (its
#                                    default: each device on a clock of its
#                                    own, phases spread over the period, rates
#                                    +-500 ppm, as a classroom's devices) or
#                                    `lockstep` (every device stepped together
#                                    once per period, as the earlier figures).
#                                    A baseline's older hapsim-load without
#                                    device clocks runs in lockstep.
#   RT_PRIORITY [0]                  --rt-priority of the server and
#                                    hapsim-load (0: normal scheduling; not
#                                    given to a baseline's older binaries)
#   SERVER_FLAGS []                  more flags for this build's server (not a
#                                    baseline's), e.g. "--dds-io-scheduling
#                                    normal" to compare a setting side by side
#   RECORDINGS [off]                 trial recording on the server, one series
#                                    each, in this order: `off`, or `on`
#                                    (--data-dir in the run's directory,
#                                    --record all: every session recorded);
#                                    repeat values to interleave runs, e.g.
#                                    "off on off on" (recording's cost is a
#                                    few % at most: compare means)
#   LINKS [loopback]                 where the clients reach the server, one
#                                    series each: `loopback` (127.0.0.1, the
#                                    shipped loopback DDS config) or a link of
#                                    the network lab (netlab/netlab.sh), as
#                                    hapsim-linkem's --host keys, e.g.
#                                    `delay_ms=0` or `delay_ms=5,loss=0.01`:
#                                    the server on lab host `server`, the
#                                    clients (and hapsim-ctl) on host
#                                    `trainees` behind that access link, DDS
#                                    on deploy/make-dds-config.sh's unicast
#                                    LAN config; the emulator is pinned to
#                                    core 1 with the clients, and its report
#                                    (packets, drops, lateness) is kept as
#                                    link.json. Lab runs need root,
#                                    /dev/net/tun and iproute2.
#
# Before and after each run the host's UDP traffic is sampled for 1 s with
# nothing of ours running; a row whose background exceeds 1000 datagrams/s is
# marked in the table (another program was using the network).
#
# Needs 2+ CPUs (taskset -c 0 / -c 1), ddsperf (cyclonedds-tools). Every
# process it starts is killed on exit; all traffic stays on 127.0.0.1
# (deploy/cyclonedds-loopback.xml, gRPC on 127.0.0.1, random test DDS
# domains 210-232) or inside the lab's namespaces (removed on exit); each
# client runs under `timeout`.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
here=$(cd "$(dirname "$0")" && pwd)
bin=$(cd "${1:-$root/build/bin}" && pwd)
out=${2:-$root/build/capacity-$(date -u +%Y%m%dT%H%M%SZ)}
COUNTS=${COUNTS:-1 8 16 32 64}
SCENES=${SCENES:-tissue_block acupuncture}
MODES=${MODES:-load bridges}
RUN_S=${RUN_S:-20}
SCRIPT=${SCRIPT:-insertion}
SCENE_PARAMS=${SCENE_PARAMS:-}
scene_param_flags=()
for p in $SCENE_PARAMS; do scene_param_flags+=(--param "$p"); done
BASELINE_BIN=${BASELINE_BIN:-}
if [ -z "${BASELINE_CLIENT_BIN:-}" ]; then
  BASELINE_CLIENT_BIN=$bin
  [ -n "$BASELINE_BIN" ] && [ -x "$BASELINE_BIN/hapsim-bridge" ] && BASELINE_CLIENT_BIN=$BASELINE_BIN
fi
DDSPERF_S=${DDSPERF_S:-10}
LINKS=${LINKS:-loopback}
CODINGS=${CODINGS:-every}
RECORDINGS=${RECORDINGS:-off}
LOAD_CLOCKS=${LOAD_CLOCKS:-own}
RT_PRIORITY=${RT_PRIORITY:-0}
case "$LOAD_CLOCKS" in
  own) load_clock_flags=() ;;
  lockstep) load_clock_flags=(--clock-phase-spread 0 --clock-rate-ppm 0) ;;
  *) echo "capacity.sh: LOAD_CLOCKS must be own or lockstep" >&2; exit 2 ;;
esac
dds_uri=file://$root/deploy/cyclonedds-loopback.xml
netlab="$root/netlab/netlab.sh"
export HAPSIM_LINKEM="$bin/hapsim-linkem"
lab=""  # the network lab of the current run, if any

die() { echo "capacity.sh: $*" >&2; exit 2; }
for n in $COUNTS; do [[ $n =~ ^[0-9]+$ && $n -ge 1 && $n -le 64 ]] || die "COUNTS: $n is not in 1..64"; done
for m in $MODES; do [[ $m == load || $m == bridges ]] || die "MODES: unknown mode $m (load, bridges)"; done
for c in $CODINGS; do [[ $c == every || $c == deadband ]] || die "CODINGS: unknown coding $c (every, deadband)"; done
for r in $RECORDINGS; do [[ $r == off || $r == on ]] || die "RECORDINGS: $r is neither off nor on"; done
for l in $LINKS; do
  [[ $l == loopback || $l =~ ^[a-z_]+=[0-9.]+(,[a-z_]+=[0-9.]+)*$ ]] ||
    die "LINKS: '$l' is neither loopback nor a link like delay_ms=5,loss=0.01"
done
if [[ " $LINKS " != " loopback " ]]; then
  [ -x "$bin/hapsim-linkem" ] || die "$bin/hapsim-linkem not found (LINKS needs the network lab)"
  "$netlab" check >/dev/null || die "LINKS needs the network lab: $("$netlab" check)"
fi
[[ $RUN_S =~ ^[0-9]+([.][0-9]+)?$ ]] || die "RUN_S must be a number of seconds"
client_timeout=$((${RUN_S%.*} + 61))
for b in hapsim-server hapsim-ctl hapsim-load hapsim-bridge; do [ -x "$bin/$b" ] || die "$bin/$b not found"; done
[ -z "$BASELINE_BIN" ] || [ -x "$BASELINE_BIN/hapsim-server" ] || die "$BASELINE_BIN/hapsim-server not found"
taskset -c 1 true 2>/dev/null || die "needs CPUs 0 and 1 (taskset -c 1 failed)"
mkdir -p "$out/runs"
out=$(cd "$out" && pwd)
: >"$out/runs.txt"

pids=()  # started in the background and not yet reaped; `timeout` leads its own process group
forget() {  # forget PID: reaped, so never signal that id again
  local keep=() p
  for p in "${pids[@]}"; do [ "$p" = "$1" ] || keep+=("$p"); done
  pids=("${keep[@]}")
}
cleanup() {
  local p
  for p in "${pids[@]}"; do kill -TERM -- "-$p" "$p" 2>/dev/null || true; done
  sleep 0.3
  for p in "${pids[@]}"; do kill -KILL -- "-$p" "$p" 2>/dev/null || true; done
  [ -z "$lab" ] || "$netlab" down "$lab" >/dev/null 2>&1 || true
}
trap cleanup EXIT
trap 'exit 130' INT TERM

new_domain() { echo $((210 + RANDOM % 23)); }

# Where the processes of a run live: on 127.0.0.1, or on the lab's hosts.
on_server=() on_clients=() server_ip=127.0.0.1 dds_flags=()
# place LINK: set the above for LINK; in a lab, bring it up (the emulator on core 1)
place() {
  if [ "$1" = loopback ]; then
    on_server=() on_clients=() server_ip=127.0.0.1 dds_flags=()
    return
  fi
  lab=cap$$
  "$netlab" up "$lab" --seconds 600 --owner $$ --realtime server "trainees=$1" >/dev/null
  taskset -pc 1 "$(cat "${HAPSIM_NETLAB_STATE:-/run/hapsim-netlab}/$lab/linkem.pid")" >/dev/null
  on_server=("$netlab" exec "$lab" server) on_clients=("$netlab" exec "$lab" trainees) server_ip=10.77.0.1
  dds_flags=(--dds-config "$out/lab-dds.xml")
}
# unplace DIR: take the lab down and keep its emulator's report in DIR/link.json
unplace() {
  [ -n "$lab" ] || return 0
  cat "/proc/$(cat "${HAPSIM_NETLAB_STATE:-/run/hapsim-netlab}/$lab/linkem.pid")/stat" >"$1/linkem_stat.txt" 2>/dev/null || true
  "$netlab" down "$lab" >/dev/null 2>&1 || true
  cp "${HAPSIM_NETLAB_STATE:-/run/hapsim-netlab}/$lab/report.json" "$1/link.json" 2>/dev/null || true
  lab=""
}
# udp_counters FILE: the Udp: lines of /proc/net/snmp where the run's processes are
# (the host, or the sum over the lab's two hosts)
udp_counters() {
  if [ -z "$lab" ]; then grep '^Udp:' /proc/net/snmp >"$1"; return; fi
  "${on_server[@]}" grep '^Udp:' /proc/net/snmp >"server_$1"
  "${on_clients[@]}" grep '^Udp:' /proc/net/snmp >"clients_$1"
  cat "server_$1" "clients_$1" |
    awk 'NR == 1 { print; next } NR == 2 || NR == 4 { for (i = 2; i <= NF; i++) sum[i] += $i; n = NF }
         END { printf "Udp:"; for (i = 2; i <= n; i++) printf " %d", sum[i]; print "" }' >"$1"
}
udp_out() { awk '/^Udp:/ { if (++line == 2) print $5 }' /proc/net/snmp; }
# background SUFFIX: the host's UDP datagrams sent in 1 s with nothing of ours running -> run.env
background() {
  local before
  before=$(udp_out); sleep 1
  echo "background_udp_per_s_$1=$(($(udp_out) - before))" >>run.env
}
# client DIR NAME: DIR/NAME if it exists, else this build's
client() { if [ -x "$1/$2" ]; then echo "$1/$2"; else echo "$bin/$2"; fi; }
snapshot() {  # snapshot PID SUFFIX: server CPU (and per named thread), UDP counters, wall clock
  cat "/proc/$1/stat" >"stat_$2.txt"
  local task
  for task in /proc/"$1"/task/*; do echo "$(cat "$task/comm" 2>/dev/null)|$(cat "$task/stat" 2>/dev/null)"; done \
      >"threads_$2.txt" || true
  # Context switches (voluntary + involuntary) summed over the server's threads.
  cat /proc/"$1"/task/*/status 2>/dev/null | awk '/^(non)?voluntary_ctxt_switches:/ {n += $2} END {print n}' \
      >"ctxt_$2.txt" || true
  udp_counters "snmp_$2.txt"
  date +%s.%N >"wall_$2.txt"
  cut -d' ' -f1-3 /proc/loadavg >"loadavg_$2.txt"
  grep -E '^cpu[01] ' /proc/stat >"cores_$2.txt"  # busy time of the server's core and the clients' core
}
# scrape_metrics SUFFIX: the server's Prometheus text (its per-session tick work) into metrics_SUFFIX.txt,
# where it has an endpoint ($metrics_port from its log; empty: none)
scrape_metrics() {
  [ -n "${metrics_port:-}" ] || return 0
  "${on_clients[@]}" /usr/bin/python3 -c 'import sys, urllib.request
sys.stdout.write(urllib.request.urlopen(sys.argv[1], timeout=5).read().decode())' \
      "http://$server_ip:$metrics_port/metrics" >"metrics_$1.txt" 2>/dev/null || rm -f "metrics_$1.txt"
}
# stop_server PID: SIGTERM, at most 10 s, then SIGKILL; appends its exit code to run.env
stop_server() {
  kill -TERM "$1" 2>/dev/null || true
  for _ in $(seq 1 100); do kill -0 "$1" 2>/dev/null || break; sleep 0.1; done
  kill -KILL "$1" 2>/dev/null || true
  local rc=0
  wait "$1" 2>/dev/null || rc=$?
  forget "$1"
  echo "server_rc=$rc" >>run.env
}

# The flags of a coding: for the server, for the clients.
coding_flags() {  # CODING server|clients
  [ "$1" = every ] || return 0
  if [ "$2" = server ]; then echo --model-deadband 0; else echo --pose-deadband-mm 0; fi
}

# run_one MODE LABEL SERVER_DIR CLIENT_DIR SCENE N [LINK] (and $coding, $recording, $recording_run)
run_one() {
  local mode=$1 label=$2 server_dir=$3 client_dir=$4 scene=$5 n=$6 link=${7:-loopback}
  local dir="$out/runs/$mode-$label-$scene-$n${7:+-$7}"
  [ "$coding" = every ] || dir+="-$coding"
  [ "$RECORDINGS" = off ] || dir+="-recording-$recording-$recording_run"
  local recording_flags=()
  [ "$recording" = off ] || recording_flags=(--data-dir "$dir/data" --record all)
  local server_coding client_coding
  read -ra server_coding <<<"$(coding_flags "$coding" server)"
  read -ra client_coding <<<"$(coding_flags "$coding" clients)"
  local client_load_clocks=("${load_clock_flags[@]}") server_rt=()
  [ "$RT_PRIORITY" = 0 ] || [ "$label" = baseline ] || server_rt=(--rt-priority "$RT_PRIORITY")
  local server_extra=()
  [ "$label" = baseline ] || read -r -a server_extra <<<"${SERVER_FLAGS:-}"
  # The tick's own work per session (hapsim_session_tick_seconds_total) beside the process's CPU; an older
  # baseline build may not have the endpoint.
  [ "$label" = baseline ] || server_extra+=(--metrics-listen "$server_ip:0")
  if [ "$label" = baseline ]; then server_coding=() client_coding=(); fi  # an older build: every tick, its own flags
  local load_help
  load_help=$("$(client "$client_dir" hapsim-load)" --help 2>/dev/null || true)  # no pipe: grep -q would cut it
  if [[ $load_help != *--clock-phase-spread* ]]; then
    client_load_clocks=()  # an older hapsim-load: lockstep, its only way
  fi
  local domain server addr i rc client_rc=0 failure="" ctl bridges=() metrics_port=""
  rm -rf "$dir" && mkdir -p "$dir"
  echo "$dir" >>"$out/runs.txt"
  echo "$(date -u +%T) $mode / $label server / $scene / N=$n (load $(cut -d' ' -f1-3 /proc/loadavg))" >&2
  cd "$dir"
  domain=$(new_domain)
  {
    echo "mode=$mode"; echo "server=$label"; echo "scene=$scene"; echo "n=$n"; echo "run_s=$RUN_S"
    echo "script=$SCRIPT"; echo "scene_params=$SCENE_PARAMS"; echo "domain=$domain"; echo "clk_tck=$(getconf CLK_TCK)"
    echo "server_bin=$server_dir/hapsim-server"; echo "client_dir=$client_dir"; echo "link=$link"
    echo "coding=$coding"; echo "recording=$recording"; echo "load_clocks=$LOAD_CLOCKS"; echo "rt_priority=$RT_PRIORITY"
    echo "server_flags=${server_extra[*]}"
  } >run.env
  background before
  place "$link"
  "${on_server[@]}" taskset -c 0 "$server_dir/hapsim-server" --listen "$server_ip:0" --port-file port \
      --max-sessions 64 --dds-domain "$domain" "${dds_flags[@]}" "${server_coding[@]}" "${recording_flags[@]}" "${server_rt[@]}" \
      "${server_extra[@]}" >server.out 2>server.log &
  server=$!; pids+=("$server")
  for _ in $(seq 1 150); do [ -s port ] && break; sleep 0.1; done
  if [ ! -s port ]; then
    echo "failure=server did not start" >>run.env; stop_server "$server"; unplace "$dir"; cd "$out"; return
  fi
  addr=$server_ip:$(cat port)
  metrics_port=$(sed -n 's/.*metrics at http:\/\/.* (port \([0-9]*\)).*/\1/p' server.log | head -1)
  ctl=("${on_clients[@]}" taskset -c 1 timeout 30 "$bin/hapsim-ctl" --server "$addr")
  for ((i = 0; i < n; i++)); do
    if ! "${ctl[@]}" create --id "cap-$i" --scene "$scene" "${scene_param_flags[@]}" >>create.out 2>>create.err; then
      failure="hapsim-ctl create cap-$i failed: $(tail -1 create.err)"; break
    fi
  done
  if [ -n "$failure" ]; then
    echo "failure=$failure" >>run.env; stop_server "$server"; unplace "$dir"; cd "$out"; return
  fi
  sleep 0.5
  "${ctl[@]}" list >list_before.txt || true
  scrape_metrics before
  snapshot "$server" before
  if [ "$mode" = load ]; then
    "${on_clients[@]}" taskset -c 1 timeout -k 5 "$client_timeout" "$(client "$client_dir" hapsim-load)" \
        --server "$addr" --dds-domain "$domain" "${dds_flags[@]}" "${client_coding[@]}" --session-prefix cap- --devices "$n" --script "$SCRIPT" --seconds "$RUN_S" \
        "${client_load_clocks[@]}" "${server_rt[@]}" \
        --json load.json --csv load.csv --server-stats >load.out 2>load.err &
    pids+=("$!")
    wait "$!" || client_rc=$?
    forget "$!"
  else
    for ((i = 0; i < n; i++)); do
      "${on_clients[@]}" taskset -c 1 timeout -k 5 "$client_timeout" "$(client "$client_dir" hapsim-bridge)" \
          --session "cap-$i" --device-id $((1000 + i)) --script "$SCRIPT" --keep-running --seconds "$RUN_S" \
          --dds-domain "$domain" "${dds_flags[@]}" "${client_coding[@]}" --log-level warn >"bridge-$i.out" 2>"bridge-$i.err" &
      bridges+=("$!"); pids+=("$!")
      sleep "$(awk -v n="$n" 'BEGIN { printf "%.4f", 1.0 / n }')"
    done
    for i in "${!bridges[@]}"; do
      rc=0; wait "${bridges[$i]}" || rc=$?
      forget "${bridges[$i]}"
      echo "$rc" >"bridge-$i.rc"
      [ "$rc" -eq 0 ] || client_rc=$rc
    done
  fi
  snapshot "$server" after
  scrape_metrics after
  "${ctl[@]}" list >list_after.txt || true
  echo "client_rc=$client_rc" >>run.env
  stop_server "$server"
  unplace "$dir"
  background after
  cd "$out"
}

# The transport baseline: ddsperf ping/pong at 1 kHz, pong on core 0 (the server's place), ping on core 1.
run_ddsperf() {  # LINK
  local link=$1 dir="$out/runs/ddsperf" domain pong uri=$dds_uri
  [ "$link" = loopback ] || dir+="-$link"
  mkdir -p "$dir"
  echo "$(date -u +%T) ddsperf ping/pong 1 kHz for ${DDSPERF_S} s ($link)" >&2
  cd "$dir"
  domain=$(new_domain)
  echo "link=$link" >run.env
  background before
  place "$link"
  [ -z "$lab" ] || uri=file://$out/lab-dds.xml
  udp_counters snmp_before.txt
  "${on_server[@]}" env CYCLONEDDS_URI="$uri" taskset -c 0 timeout -k 5 $((DDSPERF_S + 20)) \
      ddsperf -i "$domain" -D $((DDSPERF_S + 2)) pong waitset >pong.out 2>&1 &
  pong=$!; pids+=("$pong")
  "${on_clients[@]}" env CYCLONEDDS_URI="$uri" taskset -c 1 timeout -k 5 $((DDSPERF_S + 20)) \
      ddsperf -i "$domain" -D "$DDSPERF_S" ping 1kHz waitset >ping.out 2>&1 || echo "ping exited $?" >>ping.out
  wait "$pong" || true
  forget "$pong"
  udp_counters snmp_after.txt
  unplace "$dir"
  background after
  cd "$out"
}

{
  echo "date=$(date -u +%FT%TZ)"; echo "host=$(hostname)"; echo "cpus=$(nproc)"
  echo "cpu=$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //')"
  echo "commit=$(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)$(git -C "$root" diff --quiet HEAD 2>/dev/null || echo +modified)"
  echo "counts=$COUNTS"; echo "scenes=$SCENES"; echo "modes=$MODES"; echo "run_s=$RUN_S"; echo "script=$SCRIPT"; echo "scene_params=$SCENE_PARAMS"
  echo "baseline=${BASELINE_BIN:-none}"; echo "rmem_default=$(cat /proc/sys/net/core/rmem_default)"
  echo "rmem_max=$(cat /proc/sys/net/core/rmem_max)"; echo "links=$LINKS"; echo "codings=$CODINGS"
} >"$out/meta.env"
# The lab's hosts: server 10.77.0.1, trainees 10.77.0.2 (unicast peers, as deployed on a LAN).
[[ " $LINKS " == " loopback " ]] ||
  "$root/deploy/make-dds-config.sh" --interface hl0 --peer 10.77.0.1 --peer 10.77.0.2 --out "$out/lab-dds.xml"

if [ "$DDSPERF_S" != 0 ]; then
  if command -v ddsperf >/dev/null; then
    for link in $LINKS; do run_ddsperf "$link"; done
  else
    echo "capacity.sh: ddsperf not found, no transport baseline" >&2
  fi
fi
# Which modes' clients can drive the baseline server (1 s probe, tissue_block, N = 1).
baseline_modes="" coding=every recording=off recording_run=0
if [ -n "$BASELINE_BIN" ]; then
  saved_run_s=$RUN_S saved_runs=$out/runs.txt
  RUN_S=1
  for mode in $MODES; do
    probe="$out/runs/probe-$mode-baseline"
    run_one "$mode" baseline "$BASELINE_BIN" "$BASELINE_CLIENT_BIN" tissue_block 1
    rm -rf "$probe" && mv "$out/runs/$mode-baseline-tissue_block-1" "$probe"
    if grep -qs 'models_received": [1-9]' "$probe/load.json" ||
       grep -qs 'force models received [1-9]' "$probe/bridge-0.out"; then
      baseline_modes+=" $mode"
    else
      echo "capacity.sh: the $mode clients ($(client "$BASELINE_CLIENT_BIN" "hapsim-$([ "$mode" = load ] && echo load || echo bridge)")) got no force model from the baseline server: its $mode runs are skipped (see BASELINE_CLIENT_BIN)" | tee -a "$out/notes.txt" >&2
    fi
  done
  RUN_S=$saved_run_s
  : >"$saved_runs"
fi
recording_run=0
for link in $LINKS; do
 for coding in $CODINGS; do
  for mode in $MODES; do
   for recording in $RECORDINGS; do
    recording_run=$((recording_run + 1))
    for scene in $SCENES; do
      for n in $COUNTS; do
        # shellcheck disable=SC2046  # the link joins the run's name only in a lab
        run_one "$mode" current "$bin" "$bin" "$scene" "$n" $([ "$link" = loopback ] || echo "$link")
        if [[ $coding == every && " $baseline_modes " == *" $mode "* ]]; then
          run_one "$mode" baseline "$BASELINE_BIN" "$BASELINE_CLIENT_BIN" "$scene" "$n" \
              $([ "$link" = loopback ] || echo "$link")
        fi
      done
    done
   done
  done
 done
done
/usr/bin/python3 "$here/capacity_table.py" "$out" | tee "$out/capacity.md"
echo "raw outputs: $out/runs, per-run figures: $out/capacity.csv" >&2
