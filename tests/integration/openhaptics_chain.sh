#!/usr/bin/env bash
# The OpenHaptics backend in the whole chain, with the fake HD runtime
# standing in for the vendor's libHD.so: a server serving a tissue block,
# hapsim-bridge --backend openhaptics loading the fake through --hd-library.
# The fake's stylus presses 5 mm into the tissue; its own 1 kHz scheduler
# clocks the servo. Then the same with a force-output fault injected at
# 1.5 s: the bridge must stop with zero force and say why (exit 1). Then
# two styluses on one bridge (--device t1 --device t2: two fake devices on
# its one scheduler), each pressing into its own session.
# check_openhaptics_chain.py reads the fake's force logs and the bridge's output.
set -euo pipefail
source "$(dirname "$0")/lib.sh" "$1" "$2"
fake_hd=${3:?usage: $0 BIN_DIR WORK_DIR FAKE_LIBHD}
start_server "t1:tissue_block,t2:tissue_block" "${every_tick_server[@]}"
bridge() {  # bridge NAME [fake fault]
  HAPSIM_FAKE_HD_SCRIPT=press HAPSIM_FAKE_HD_LOG="$work/$1.fake.csv" HAPSIM_FAKE_HD_FAULT="${2:-}" \
    "$bin/hapsim-bridge" --backend openhaptics --hd-library "$fake_hd" --session t1 --device-id 7 "${every_tick_client[@]}" \
      --dds-domain "$domain" --seconds 3 --max-force-n 2.0 >"$1.out" 2>"$1.log" || echo "$?" >"$1.rc"
}
bridge pressed
bridge faulted "force_fault:1500"
HAPSIM_FAKE_HD_SCRIPT=press HAPSIM_FAKE_HD_LOG="$work/two.fake.csv" \
  "$bin/hapsim-bridge" --backend openhaptics --hd-library "$fake_hd" --device t1 --device t2 --device-id 17 \
    "${every_tick_client[@]}" --dds-domain "$domain" --seconds 2 --max-force-n 2.0 >two.out 2>two.log || echo "$?" >two.rc
stop_process server_rc "$server"
pids=()
[ "$server_rc" = 0 ] || { echo "server exited with $server_rc"; cat server.log; exit 1; }
cat pressed.out faulted.log two.out
/usr/bin/python3 "$here/check_openhaptics_chain.py" "$work"
