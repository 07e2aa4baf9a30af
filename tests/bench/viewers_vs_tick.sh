#!/usr/bin/env bash
# Do viewers disturb the 1 kHz loop? (not in CI: run by hand on a quiet
# 2-core machine; figures in docs/performance.md). One tissue_block session
# on a hapsim-server pinned to core 0 with one tick worker; a hapsim-bridge
# on core 1 pressing it with a pose and a force model every tick; N headless
# viewers of the same session on core 1. For every N, the server runs twice
# back to back: normal scheduling, then --rt-priority on the server (tick
# worker at SCHED_FIFO, receive threads one above) and on the bridge (its
# servo thread, its receive threads one above). Reports the bridge's round trip,
# the server's late ticks and worst lateness, its CPU, and the viewers'
# frames.
#
#   tests/bench/viewers_vs_tick.sh [BIN_DIR] [OUT_DIR]
#
# Environment: VIEWERS [0 25 50 100], RT [off on], RUN_S [10],
# RT_PRIORITY [40], RT_WHERE [server bridge] (who gets it in `on` runs),
# SERVER_CPUS [0] (the server's taskset), SERVER_FLAGS [] (e.g. with
# SERVER_CPUS=0,1: "--tick-cpus 0", the tick path alone on core 0). Needs root (or CAP_SYS_NICE) for the `on` runs; all
# traffic on 127.0.0.1 with the shipped loopback DDS config.
set -euo pipefail
repo=$(cd "$(dirname "$0")/../.." && pwd)
bin=$(cd "${1:-$repo/build/bin}" && pwd)
out=${2:-$repo/build/viewers-vs-tick-$(date -u +%Y%m%dT%H%M%SZ)}
VIEWERS=${VIEWERS:-0 25 50 100}
RT=${RT:-off on}
RUN_S=${RUN_S:-10}
RT_PRIORITY=${RT_PRIORITY:-40}
RT_WHERE=${RT_WHERE:-server bridge}  # which processes get --rt-priority in the `on` runs
mkdir -p "$out"
pids=()
cleanup() { for p in "${pids[@]}"; do kill -KILL "$p" 2>/dev/null || true; done; }
trap cleanup EXIT
cpu_ticks() { awk '{ print $14 + $15 }' "/proc/$1/stat"; }

run() {  # N RT
  local n=$1 rt=$2 dir="$out/viewers-$1-rt-$2" domain=$((220 + RANDOM % 12)) server i
  local -a viewers=()
  mkdir -p "$dir" && cd "$dir"
  local server_rt=() bridge_rt=()
  if [ "$rt" = on ]; then
    [[ " $RT_WHERE " == *" server "* ]] && server_rt=(--rt-priority "$RT_PRIORITY")
    [[ " $RT_WHERE " == *" bridge "* ]] && bridge_rt=(--rt-priority "$RT_PRIORITY")
  fi
  taskset -c "${SERVER_CPUS:-0}" "$bin/hapsim-server" --listen 127.0.0.1:0 --port-file port --workers 1 \
      --dds-domain "$domain" --sessions s:tissue_block --model-deadband 0 "${server_rt[@]}" ${SERVER_FLAGS:-} \
      >server.out 2>server.log &
  server=$!; pids+=("$server")
  for _ in $(seq 100); do [ -s port ] && break; sleep 0.05; done
  local addr="127.0.0.1:$(cat port)"
  for ((i = 0; i < n; i++)); do
    taskset -c 1 "$bin/hapsim-viewer" --headless --server "$addr" --session s --seconds $((RUN_S + 2)) \
        >"viewer-$i.out" 2>"viewer-$i.log" &
    pids+=("$!"); viewers+=("$!")
  done
  sleep 1.5  # the viewers' keyframes out of the way
  local cpu_before; cpu_before=$(cpu_ticks "$server")
  taskset -c 1 "$bin/hapsim-bridge" --session s --dds-domain "$domain" "${bridge_rt[@]}" --script insertion --depth-mm 5 \
      --hold-s 60 --start-height-mm 2 --seconds "$RUN_S" --pose-deadband-mm 0 >bridge.out 2>bridge.log
  local cpu_after; cpu_after=$(cpu_ticks "$server")
  "$bin/hapsim-ctl" --server "$addr" info s >info.txt
  [ ${#viewers[@]} -eq 0 ] || wait "${viewers[@]}" 2>/dev/null || true
  kill -TERM "$server"; wait "$server" 2>/dev/null || true
  pids=()
  local rtt late worst frames_min frames_mean cpu
  rtt=$(grep -o 'round trip p50 [0-9.]* / p99 [0-9.]*' bridge.out | awk '{ print $4 " / " $7 }')
  late=$(grep -o 'late_ticks=[0-9]*' info.txt | cut -d= -f2)
  worst=$(grep -o 'max_tick_lateness_s=[0-9.]*' info.txt | cut -d= -f2)
  frames_min=$(cat viewer-*.out 2>/dev/null | grep -o ', frames [0-9]*' | awk '{ print $3 }' | sort -n | head -1 || true)
  frames_mean=$(cat viewer-*.out 2>/dev/null | grep -o ', frames [0-9]*' \
      | awk '{ s += $3; n++ } END { if (n) printf "%.0f", s / n }' || true)
  cpu=$(awk -v a="$cpu_before" -v b="$cpu_after" -v hz="$(getconf CLK_TCK)" -v s="$RUN_S" \
      'BEGIN { printf "%.2f", (b - a) / hz / s }')
  [ "$rt" = on ] && rt="on: ${RT_WHERE// /+}"
  printf '| %s | %s | %s | %s | %.3f | %s | %s / %s |\n' "$n" "$rt" "$rtt" "$late" \
      "$(awk -v w="$worst" 'BEGIN { print w * 1000 }')" "$cpu" "${frames_min:--}" "${frames_mean:--}" \
      | tee -a "$out/table.md"
  cd "$out"
}

{
  echo "viewers_vs_tick.sh: $(date -u +%FT%TZ), $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2-), RUN_S=$RUN_S"
  echo
  echo "| viewers | real-time | bridge round trip p50 / p99 [ms] | late ticks | worst lateness [ms] | server CPU [cores] | viewer frames min / mean |"
  echo "|---|---|---|---|---|---|---|"
} | tee "$out/table.md"
for n in $VIEWERS; do
  for rt in $RT; do run "$n" "$rt"; done
done
echo "raw outputs in $out"
