#!/usr/bin/env bash
# Two real servers on one DDS domain, each serving a session "t1" (a tissue
# block on one, the acupuncture scene on the other — everyone's defaults
# make this likely on a lab network), and one hapsim-bridge driving "t1".
# The bridge must render one server's models only: it follows the first
# server that answers and drops and counts the other's. Each server must
# warn that another one publishes force models in t1's partition.
# check_two_servers.py reads the output.
set -euo pipefail
source "$(dirname "$0")/lib.sh" "$@"
start_server "t1:tissue_block"
mv port a.port; mv server.out a.out; mv server.log a.log  # open files follow the rename
server_a=$server
start_server "t1:acupuncture"
mv port b.port; mv server.out b.out; mv server.log b.log
server_b=$server
"$bin/hapsim-bridge" --session t1 --device-id 7 --dds-domain "$domain" --script insertion --depth-mm 8 \
    --seconds 3 --trace bridge.csv >bridge.out 2>bridge.log
stop_process rc_a "$server_a"
stop_process rc_b "$server_b"
pids=()
[ "$rc_a" = 0 ] && [ "$rc_b" = 0 ] || { echo "a server exited with $rc_a / $rc_b"; exit 1; }
cat bridge.out
/usr/bin/python3 "$here/check_two_servers.py" "$work"
