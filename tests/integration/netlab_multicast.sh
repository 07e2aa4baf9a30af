#!/usr/bin/env bash
# The LAN DDS config's other discovery, in the network lab: no peer list,
# participants find each other by multicast SPDP on the chosen interface
# (deploy/make-dds-config.sh --discovery multicast), data unicast. A server
# host and two trainee hosts 1 ms away, each bridge pressing into its own
# session with the shipped defaults. check_netlab_multicast.py checks that
# each bridge found the server and felt its tissue, and that multicast
# carried discovery only. Exits 77 (skipped) where namespaces cannot be made.
set -euo pipefail
source "$(dirname "$0")/lib.sh" "$@"
source "$here/netlab_lib.sh"
lab_up mc --seconds 60 --realtime server t1=delay_ms=1 t2=delay_ms=1
"$repo/deploy/make-dds-config.sh" --interface hl0 --discovery multicast --out dds.xml
on_bg server "$bin/hapsim-server" --listen 10.77.0.1:50051 --sessions s1:tissue_block,s2:tissue_block \
    --dds-config dds.xml >server.out 2>server.log
server=$!; pids+=("$server")
sleep 1.0
for t in 1 2; do
  on_bg "t$t" "$bin/hapsim-bridge" --session "s$t" --device-id "$t" --dds-config dds.xml --script insertion \
      --depth-mm 4 --speed-mm-s 10 --hold-s 0.5 --start-height-mm 5 --seconds 3 --keep-running \
      >"t$t.out" 2>"t$t.log"
  pids+=("$!"); echo "$!" >"t$t.pid"
done
for t in 1 2; do wait "$(cat "t$t.pid")" && echo 0 >"t$t.rc" || echo $? >"t$t.rc"; done
stop_process server_rc "$server"
echo "$server_rc" >server.rc
"$netlab" down "$lab"
cp "$HAPSIM_NETLAB_STATE/$lab/report.json" link.json
cat t1.out t2.out
/usr/bin/python3 "$here/check_netlab_multicast.py" "$work"
