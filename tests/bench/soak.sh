#!/usr/bin/env bash
# Soak (not in CI): SESSIONS tissue_block sessions driven by
# hapsim-load, VIEWERS viewers following them, one more viewer connecting
# and disconnecting every second (CHURN=0: not), for SECONDS; the server pinned to core 0,
# every client to core 1. Samples the server's RSS every 10 s; writes
# rss.csv, load.json/load.out (late ticks, round trip, model age),
# intervals.csv (round trip and model age per minute) and a
# summary to OUT_DIR. Loopback only; every process is killed on exit.
# Usage: tests/bench/soak.sh BIN_DIR OUT_DIR   (SESSIONS=32 VIEWERS=8 SECONDS_TOTAL=600 CHURN=1)
set -euo pipefail
bin=$(cd "${1:?usage: $0 BIN_DIR OUT_DIR}" && pwd)  # absolute: the script works inside OUT_DIR
out=${2:?usage: $0 BIN_DIR OUT_DIR}
sessions=${SESSIONS:-32}; viewers=${VIEWERS:-8}; seconds=${SECONDS_TOTAL:-600}; churning=${CHURN:-1}
rm -rf "$out" && mkdir -p "$out" && cd "$out"
domain=$((150 + RANDOM % 60))
pids=()
cleanup() { for p in "${pids[@]}"; do kill -KILL "$p" 2>/dev/null || true; done; }
trap cleanup EXIT
# Every pose and every model (the runtime's worst case; the shipped deadband coding sends ~5 %).
taskset -c 0 "$bin/hapsim-server" --listen 127.0.0.1:0 --port-file port --dds-domain "$domain" --max-sessions 64 \
    --model-deadband 0 >server.out 2>server.log &
server=$!; pids+=("$server")
for _ in $(seq 1 100); do [ -s port ] && break; sleep 0.1; done
[ -s port ] || { echo "soak: the server did not start:" >&2; cat server.log >&2; exit 1; }
addr=127.0.0.1:$(cat port)
taskset -c 1 "$bin/hapsim-load" --server "$addr" --dds-domain "$domain" --pose-deadband-mm 0 --create tissue_block --devices "$sessions" \
    --seconds "$seconds" --json load.json --interval-s 60 --intervals-csv intervals.csv >load.out 2>load.err &
load=$!; pids+=("$load")
sleep 3  # sessions created and streaming
for v in $(seq 0 $((viewers - 1))); do
  taskset -c 1 "$bin/hapsim-viewer" --headless --server "$addr" --session "load-$v" --seconds $((seconds + 5)) >"viewer$v.out" 2>/dev/null &
  pids+=("$!")
done
# The churning viewer: connects, takes a keyframe, disconnects, every second.
churn=
if [ "$churning" = 1 ]; then
  ( while true; do timeout 1 taskset -c 1 "$bin/hapsim-viewer" --headless --server "$addr" --session load-0 --seconds 0.8 \
        >/dev/null 2>&1 || true; done ) &
  churn=$!; pids+=("$churn")
fi
echo "t_s,rss_kib" >rss.csv
start=$(date +%s)
while kill -0 "$load" 2>/dev/null; do
  echo "$(( $(date +%s) - start )),$(awk '/VmRSS/ {print $2}' /proc/$server/status)" >>rss.csv
  sleep 10
done
wait "$load" || true
[ -n "$churn" ] && kill "$churn" 2>/dev/null || true
kill -TERM "$server"; wait "$server" || echo "server exit code $?" >>summary.txt
head -1 rss.csv >/dev/null
{
  echo "soak: $sessions sessions, $viewers viewers + $churning churning, ${seconds} s"
  echo "server RSS (KiB) first/after 60 s/last: $(sed -n 2p rss.csv | cut -d, -f2) / $(awk -F, 'NR>1 && $1>=60 {print $2; exit}' rss.csv) / $(tail -1 rss.csv | cut -d, -f2)"
  grep -E "round trip|model age|late|sessions" load.out | head -8
  tail -2 server.out
  echo "round trip / model age per minute (ms): end_s p50 p99 max / p50 p99 max"
  awk -F, 'NR>1 {printf "  %6.0f  %.3f %.3f %.2f / %.3f %.3f %.2f\n", $1, $3, $4, $5, $7, $8, $9}' intervals.csv
} | tee -a summary.txt
