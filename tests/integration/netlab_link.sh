#!/usr/bin/env bash
# hapsim across emulated links (netlab/netlab.sh: network namespaces joined
# by hapsim-linkem): a server host; a trainee host 10 ms away; a second
# trainee 10 ms away whose link is cut for 2 s mid-press, with a viewer of
# its own session on the same host; a viewer host 25 ms away with 1 % loss
# each way. gRPC on TLS with a class's tokens; every
# process uses the LAN DDS config
# deploy/make-dds-config.sh writes (unicast peers), gRPC on the lab
# addresses. check_netlab_link.py checks the link itself (a UDP echo's round
# trips and loss, a TCP exchange), the bridge's round trip and transparency
# at 20 ms, the cut stylus warning, fading, disarming and recovering, and
# the far viewer's frames (and another trainee's token refused across the
# link), and the cut host's viewer streaming again after the cut. Exits 77 (skipped) where namespaces cannot be made.
set -euo pipefail
source "$(dirname "$0")/lib.sh" "$@"
source "$here/netlab_lib.sh"
lab_up it --seconds 120 --realtime \
    server trainee=delay_ms=10 cut=delay_ms=10,outage=5+2 viewer=delay_ms=25,loss=0.01
"$repo/deploy/make-dds-config.sh" --interface hl0 --peer 10.77.0.1 --peer 10.77.0.2 --peer 10.77.0.3 \
    --out dds.xml
on() { "$netlab" exec "$lab" "$@"; }

# hapsim across it. Lab time: the cut host's outage is at 5-7 s, while its bridge presses (from ~2 s to ~10.5 s).
# A class on TLS with tokens (sessions t1, t2), as a skills lab runs it.
bash "$repo/deploy/make-dev-certs.sh" certs 10.77.0.1 >/dev/null
bash "$repo/deploy/make-class.sh" class lab-101 2 tissue_block >/dev/null
on_bg server "$bin/hapsim-server" --listen 10.77.0.1:50051 --class-config class/class.toml \
    --tls-cert certs/server.pem --tls-key certs/server.key --dds-config dds.xml >server.out 2>server.log
server=$!; pids+=("$server")
sleep 1.5
on_bg trainee "$bin/hapsim-bridge" --session t1 --dds-config dds.xml --script insertion --depth-mm 5 \
    --speed-mm-s 10 --hold-s 0.5 --start-height-mm 10 --seconds 3.6 --keep-running --trace trace.csv \
    >bridge.out 2>bridge.log
bridge=$!; pids+=("$bridge")
# Pressing 3 mm from lab time ~3 s to the end, through the outage.
on_bg cut "$bin/hapsim-bridge" --session t2 --dds-config dds.xml --script insertion --depth-mm 3 \
    --speed-mm-s 10 --hold-s 30 --start-height-mm 2 --seconds 9 --trace cut_trace.csv \
    >cut.out 2>cut.log
cut_bridge=$!; pids+=("$cut_bridge")
# The cut trainee's own view, through the cut: from lab time ~1.6 s to ~11.6 s.
on_bg cut "$bin/hapsim-viewer" --headless --server 10.77.0.1:50051 --session t2 --seconds 10 \
    --tls-ca certs/ca.pem --token-file class/tokens/trainee2.token >cut_viewer.out 2>cut_viewer.log
cut_viewer=$!; pids+=("$cut_viewer")
on_bg viewer "$bin/hapsim-viewer" --headless --server 10.77.0.1:50051 --session t1 --seconds 6 \
    --tls-ca certs/ca.pem --token-file class/tokens/trainee1.token >viewer.out 2>viewer.log
viewer=$!; pids+=("$viewer")
wait "$bridge" && echo 0 >bridge.rc || echo $? >bridge.rc
wait "$cut_bridge" && echo 0 >cut.rc || echo $? >cut.rc
wait "$viewer" && echo 0 >viewer.rc || echo $? >viewer.rc
wait "$cut_viewer" && echo 0 >cut_viewer.rc || echo $? >cut_viewer.rc
# Across the link too: another trainee's token cannot watch t1.
on viewer "$bin/hapsim-viewer" --headless --server 10.77.0.1:50051 --session t1 --seconds 2 \
    --tls-ca certs/ca.pem --token-file class/tokens/trainee2.token >intruder.out 2>intruder.log \
    && echo 0 >intruder.rc || echo $? >intruder.rc
stop_process server_rc "$server"
echo "$server_rc" >server.rc
# The link as sockets see it (after hapsim, whose cut host's outage is timed from the lab's start).
on_bg server /usr/bin/python3 "$repo/netlab/link_probe.py" echo 7777
echo_server=$!; pids+=("$echo_server")
sleep 0.3
on trainee /usr/bin/python3 "$repo/netlab/link_probe.py" probe 10.77.0.1 7777 200 0.005 >probe_trainee.json
on viewer /usr/bin/python3 "$repo/netlab/link_probe.py" probe 10.77.0.1 7777 1000 0.002 >probe_viewer.json
kill -KILL "$echo_server"; wait "$echo_server" 2>/dev/null || true
"$netlab" down "$lab"
cp "$HAPSIM_NETLAB_STATE/$lab/report.json" link.json
cat bridge.out cut.out viewer.out cut_viewer.out
/usr/bin/python3 "$here/check_netlab_link.py" "$work" "$repo"
