#!/usr/bin/env bash
# Haptic transparency off loopback (not in CI: ~10 min; run by hand on a
# quiet machine). For every LINK x SCENE: a network lab (netlab/netlab.sh)
# with a server host and a trainee host whose access link has the LINK's
# delay, jitter and loss; hapsim-server on the server host (pinned to core 0)
# with one session of SCENE; one hapsim-bridge on the trainee host (core 1)
# running the scene's script with --trace; a headless hapsim-viewer on a
# viewer host with the same link (core 0), watching meanwhile. Both use the LAN DDS config that
# deploy/make-dds-config.sh writes (unicast peers), gRPC on the lab address.
# transparency_table.py compares, tick by tick, the force the bridge
# rendered with the force the physics computed for the same pose (the trace's
# phys_* columns: the model that echoes the pose, evaluated at it: so every
# pose and every model is sent here, --pose-deadband-mm 0 and
# --model-deadband 0; the deadband coding is measured by tests/loop) and
# prints the table.
#
#   tests/bench/offloopback.sh [BIN_DIR] [OUT_DIR]
#
# Environment (defaults in brackets):
#   DELAYS_MS [0 5 10 25 50 100 500]   one-way delay of the trainee's link
#   LOSSES [0 0.01 0.1]                loss per packet, each direction
#   JITTER_RUNS ["10:10"]              extra runs DELAY_MS:JITTER_MS (uniform ±, no reordering)
#   SCENES [tissue_block acupuncture cutting vessel]
#
# Needs root, iproute2, /dev/net/tun and 2 CPUs. Traffic stays inside the
# lab's namespaces; the lab is removed on any exit.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
here=$(cd "$(dirname "$0")" && pwd)
bin=$(cd "${1:-$root/build/bin}" && pwd)
out=${2:-$root/build/offloopback-$(date -u +%Y%m%dT%H%M%SZ)}
DELAYS_MS=${DELAYS_MS-0 5 10 25 50 100 500}
LOSSES=${LOSSES-0 0.01 0.1}
JITTER_RUNS=${JITTER_RUNS-10:10}
SCENES=${SCENES-tissue_block acupuncture cutting vessel}
netlab="$root/netlab/netlab.sh"
export HAPSIM_LINKEM="$bin/hapsim-linkem"
lab=tb$$
mkdir -p "$out/runs"
"$netlab" check >/dev/null || { "$netlab" check; exit 77; }
trap '"$netlab" down $lab >/dev/null 2>&1 || true' EXIT
"$root/deploy/make-dds-config.sh" --interface hl0 --peer 10.77.0.1 --peer 10.77.0.2 --out "$out/dds.xml"

# The scene's script: FLAGS for hapsim-bridge, from a start height that
# leaves discovery (a few round trips) done before the tool touches, and
# --seconds for one motion plus two round trips (the last answers) and 0.5 s.
script_flags() {  # SCENE ROUND_TRIP_S
  /usr/bin/python3 - "$1" "$2" <<'PY'
import sys
scene, rtt = sys.argv[1], float(sys.argv[2])
lead = round(10 + 10 * 4 * rtt, 1)  # mm: 10 mm/s x 4 round trips
if scene == "cutting":  # approach, press 1.5 mm, 12 mm stroke, lift, at 5 mm/s
    motion, flags = (2 * lead + 2 * 1.5 + 12) / 5, "--script cut --depth-mm 1.5 --speed-mm-s 5 --entry-x-mm -6 --cut-length-mm 12"
else:  # one insertion cycle: approach, press, hold, withdraw at 10 mm/s
    depth, hold = {"tissue_block": (5, 0.5), "acupuncture": (14, 0.3), "vessel": (2, 0.5)}[scene]
    motion, flags = 2 * (lead + depth) / 10 + hold, f"--script insertion --depth-mm {depth} --speed-mm-s 10 --hold-s {hold}"
print(f"{flags} --start-height-mm {lead} --keep-running --seconds {motion + 2 * rtt + 0.5:.2f}")
PY
}

run_one() {  # NAME LINK SCENE ROUND_TRIP_S
  local name=$1 link=$2 scene=$3 rtt_s=$4 dir="$out/runs/$1-$3" server_pid viewer_pid
  mkdir -p "$dir"
  "$netlab" up "$lab" --seconds 300 --owner $$ --realtime server "trainee${link:+=$link}" "viewer${link:+=$link}"
  "$netlab" exec "$lab" server taskset -c 0 "$bin/hapsim-server" --listen 10.77.0.1:50051 --workers 1 \
      --sessions "s:$scene" --dds-config "$out/dds.xml" --log-level warn --model-deadband 0 \
      >"$dir/server.out" 2>"$dir/server.log" &
  server_pid=$!
  sleep 1.5
  local flags
  flags=$(script_flags "$scene" "$rtt_s")
  # A headless viewer on its own host with the trainee's link, watching the session meanwhile (core 0).
  "$netlab" exec "$lab" viewer taskset -c 0 timeout 120 "$bin/hapsim-viewer" --headless --server 10.77.0.1:50051 \
      --session s --seconds "${flags##*--seconds }" >"$dir/viewer.out" 2>"$dir/viewer.log" &
  viewer_pid=$!
  # shellcheck disable=SC2086
  "$netlab" exec "$lab" trainee taskset -c 1 timeout 120 "$bin/hapsim-bridge" --session s --dds-config "$out/dds.xml" \
      --pose-deadband-mm 0 $flags --trace "$dir/trace.csv" >"$dir/bridge.out" 2>"$dir/bridge.log" || echo "bridge exit $? ($name $scene)" >&2
  wait "$viewer_pid" 2>/dev/null || echo "viewer exit ($name $scene)" >&2
  kill -TERM "$server_pid" 2>/dev/null || true
  wait "$server_pid" 2>/dev/null || true
  "$netlab" down "$lab"
  cp "/run/hapsim-netlab/$lab/report.json" "$dir/link.json" 2>/dev/null || true
  echo "$name $scene $link" >"$dir/condition"
}

for delay in $DELAYS_MS; do
  for loss in $LOSSES; do
    rtt=$(/usr/bin/python3 -c "print(2 * $delay / 1000)")
    for scene in $SCENES; do
      run_one "d${delay}_l${loss}" "delay_ms=$delay,loss=$loss" "$scene" "$rtt"
    done
  done
done
for run in $JITTER_RUNS; do
  delay=${run%%:*} jitter=${run#*:}
  rtt=$(/usr/bin/python3 -c "print(2 * ($delay + $jitter) / 1000)")
  for scene in $SCENES; do
    run_one "d${delay}_j${jitter}" "delay_ms=$delay,jitter_ms=$jitter" "$scene" "$rtt"
  done
done
/usr/bin/python3 "$here/transparency_table.py" "$out/runs" | tee "$out/transparency.md"
