#!/usr/bin/env bash
# How long a trainee waits for the first force after starting a bridge
# (DDS discovery of the server, then the first model), on a lossy link in
# the network lab: RUNS bridge starts against one server, each bridge's
# "first force model N s after the servo started" line.
#
#   tests/bench/first_force.sh [BIN_DIR] [OUT_DIR]
#
# Environment: RUNS [10], LINK ["delay_ms=10,loss=0.1"] (the trainee's),
# DDS_CONFIG_FLAGS [""] (more flags for deploy/make-dds-config.sh), or DDS_CONFIG (a config file to use instead).
# Needs root, iproute2 and /dev/net/tun; the lab is removed on any exit.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
bin=$(cd "${1:-$root/build/bin}" && pwd)
out=${2:-$root/build/first-force-$(date -u +%Y%m%dT%H%M%SZ)}
RUNS=${RUNS-10}
LINK=${LINK-delay_ms=10,loss=0.1}
netlab="$root/netlab/netlab.sh"
export HAPSIM_LINKEM="$bin/hapsim-linkem"
lab=ff$$
mkdir -p "$out"
"$netlab" check >/dev/null || { "$netlab" check; exit 77; }
trap '"$netlab" down $lab >/dev/null 2>&1 || true' EXIT
if [ -n "${DDS_CONFIG:-}" ]; then
  cp "$DDS_CONFIG" "$out/dds.xml.new" && mv "$out/dds.xml.new" "$out/dds.xml"
else
  # shellcheck disable=SC2086
  "$root/deploy/make-dds-config.sh" --interface hl0 --peer 10.77.0.1 --peer 10.77.0.2 ${DDS_CONFIG_FLAGS:-} \
      --out "$out/dds.xml" >/dev/null
fi
"$netlab" up "$lab" --seconds $((30 + 6 * RUNS)) --owner $$ server "trainee=$LINK" >/dev/null
"$netlab" exec "$lab" server "$bin/hapsim-server" --listen 10.77.0.1:50051 --sessions s:tissue_block \
    --dds-config "$out/dds.xml" --log-level warn >"$out/server.out" 2>"$out/server.log" &
server=$!
sleep 1.5
for i in $(seq 1 "$RUNS"); do
  "$netlab" exec "$lab" trainee "$bin/hapsim-bridge" --session s --dds-config "$out/dds.xml" --script insertion \
      --depth-mm 3 --speed-mm-s 10 --hold-s 5 --start-height-mm 0 --seconds 4 >"$out/bridge_$i.out" 2>"$out/bridge_$i.log" || true
done
kill -TERM "$server" 2>/dev/null || true
wait "$server" 2>/dev/null || true
/usr/bin/python3 - "$out" "$RUNS" "$LINK" <<'PY'
import re, sys
out, runs, link = sys.argv[1], int(sys.argv[2]), sys.argv[3]
waits = []
for i in range(1, runs + 1):
    m = re.search(r"first force model ([\d.]+) s", open(f"{out}/bridge_{i}.out").read())
    waits.append(float(m.group(1)) if m else float("inf"))
waits.sort()
print(f"link {link}: first force after start, {runs} bridge starts (s): " + " ".join(f"{w:.3f}" for w in waits))
print(f"median {waits[len(waits) // 2]:.3f} s, worst {waits[-1]:.3f} s")
PY
