#!/usr/bin/env bash
# Perceptual deadband coding, side by side with the every-tick stream (not
# in CI; ~1 min). For every SCENE, the same scripted motion twice on
# loopback: a server and bridge sending a model and a pose every tick
# (--model-deadband 0, --pose-deadband-mm 0), then with the deadbands below
# (the shipped defaults).
# Server on core 0, bridge on core 1. deadband_table.py prints packet
# shares and the force agreement.
#
#   tests/bench/deadband.sh [BIN_DIR] [OUT_DIR]
#
# Environment (defaults in brackets):
#   SCENES [tissue_block acupuncture cutting vessel]
#   SERVER_DEADBAND ["--model-deadband 0.07 --model-keepalive-ms 25"]
#   BRIDGE_DEADBAND ["--pose-deadband-mm 0.05 --pose-keepalive-ms 25"]
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
here=$(cd "$(dirname "$0")" && pwd)
bin=$(cd "${1:-$root/build/bin}" && pwd)
out=${2:-$root/build/deadband-$(date -u +%Y%m%dT%H%M%SZ)}
SCENES=${SCENES-tissue_block acupuncture cutting vessel}
SERVER_DEADBAND=${SERVER_DEADBAND-"--model-deadband 0.07 --model-keepalive-ms 25"}
BRIDGE_DEADBAND=${BRIDGE_DEADBAND-"--pose-deadband-mm 0.05 --pose-keepalive-ms 25"}
domain=$((150 + RANDOM % 60))
mkdir -p "$out/runs"
server=""
trap '[ -z "$server" ] || kill -KILL "$server" 2>/dev/null || true' EXIT

script_flags() {  # SCENE
  case $1 in
    cutting) echo "--script cut --depth-mm 1.5 --speed-mm-s 5 --entry-x-mm -6 --cut-length-mm 12 --start-height-mm 10 --seconds 7.5" ;;
    # One insertion cycle (approach, press, hold 1 s, withdraw at 10 mm/s), then 0.5 s.
    acupuncture) echo "--script insertion --depth-mm 14 --speed-mm-s 10 --hold-s 1 --start-height-mm 10 --seconds 6.3" ;;
    vessel) echo "--script insertion --depth-mm 2 --speed-mm-s 10 --hold-s 1 --start-height-mm 10 --seconds 3.9" ;;
    *) echo "--script insertion --depth-mm 5 --speed-mm-s 10 --hold-s 1 --start-height-mm 10 --seconds 4.5" ;;
  esac
}

run() {  # SCENE NAME SERVER_FLAGS BRIDGE_FLAGS
  local dir="$out/runs/$1-$2"
  mkdir -p "$dir"
  # shellcheck disable=SC2086
  taskset -c 0 "$bin/hapsim-server" --listen 127.0.0.1:0 --workers 1 --sessions "s:$1" --dds-domain "$domain" \
      --log-level warn $3 >"$dir/server.out" 2>"$dir/server.log" &
  server=$!
  sleep 1.5
  # shellcheck disable=SC2086
  taskset -c 1 "$bin/hapsim-bridge" --session s --dds-domain "$domain" $(script_flags "$1") $4 \
      --keep-running --trace "$dir/trace.csv" >"$dir/bridge.out" 2>"$dir/bridge.log"
  kill -TERM "$server"; wait "$server" || true
  server=""
}

for scene in $SCENES; do
  run "$scene" every "--model-deadband 0" "--pose-deadband-mm 0"
  run "$scene" deadband "$SERVER_DEADBAND" "$BRIDGE_DEADBAND"
done
/usr/bin/python3 "$here/deadband_table.py" "$out/runs" | tee "$out/deadband.md"
