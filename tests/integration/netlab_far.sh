#!/usr/bin/env bash
# hapsim 50 ms away (100 ms round trip) and a host whose network interface
# vanishes (netlab/netlab.sh: network namespaces joined by hapsim-linkem).
# check_netlab_far.py checks: the far bridge's watchdog sees the delay (the
# physics age is the round trip: a felt-lag warning, full force, no fade);
# the far viewer gets >= 50 frames/s (its ack window grows by the round
# trip); a bridge and then the server whose interface was deleted stop on
# SIGTERM within their teardown bounds, without flooding their logs; with
# the LAN config, multicast carries discovery only (every model and pose
# unicast, not sent to the whole LAN).
# Exits 77 (skipped) where namespaces cannot be made.
set -euo pipefail
source "$(dirname "$0")/lib.sh" "$@"
source "$here/netlab_lib.sh"
lab_up far --seconds 90 --realtime server far=delay_ms=50 lost=delay_ms=1
"$repo/deploy/make-dds-config.sh" --interface hl0 --peer 10.77.0.1 --peer 10.77.0.2 --peer 10.77.0.3 \
    --out dds.xml
# Milliseconds since the epoch.
now_ms() { echo $(( $(date +%s%N) / 1000000 )); }

on_bg server "$bin/hapsim-server" --listen 10.77.0.1:50051 --sessions far:tissue_block,lost:tissue_block \
    --dds-config dds.xml "${every_tick_server[@]}" >server.out 2>server.log
server=$!; pids+=("$server")
sleep 1.5
on_bg far "$bin/hapsim-bridge" --session far --dds-config dds.xml "${every_tick_client[@]}" --script insertion --depth-mm 5 \
    --speed-mm-s 10 --hold-s 0.5 --start-height-mm 10 --seconds 6 --keep-running >far.out 2>far.log
far=$!; pids+=("$far")
on_bg far "$bin/hapsim-viewer" --headless --server 10.77.0.1:50051 --session far --seconds 6 \
    >viewer.out 2>viewer.log
viewer=$!; pids+=("$viewer")
on_bg lost "$bin/hapsim-bridge" --session lost --dds-config dds.xml "${every_tick_client[@]}" --script insertion --depth-mm 3 \
    --speed-mm-s 10 --hold-s 30 --start-height-mm 2 --seconds 60 >lost.out 2>lost.log
lost=$!; pids+=("$lost")
sleep 3
# The lost host's interface vanishes (a cable pulled, a VPN dropped); Cyclone's sends fail from now on.
ip -n "hapsim-$lab-lost" link del hl0
sleep 1.5
start=$(now_ms)
stop_process lost_rc "$lost"
echo "$lost_rc $(( $(now_ms) - start ))" >lost.stop
wait "$far" && echo 0 >far.rc || echo $? >far.rc
wait "$viewer" && echo 0 >viewer.rc || echo $? >viewer.rc
# Then the server's own interface.
ip -n "hapsim-$lab-server" link del hl0
sleep 1.5
start=$(now_ms)
stop_process server_rc "$server"
echo "$server_rc $(( $(now_ms) - start ))" >server.stop
"$netlab" down "$lab"
cp "$HAPSIM_NETLAB_STATE/$lab/report.json" link.json
cat far.out viewer.out
/usr/bin/python3 "$here/check_netlab_far.py" "$work"
