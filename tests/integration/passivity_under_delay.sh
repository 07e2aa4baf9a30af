#!/usr/bin/env bash
# The local force model and the passivity controller on a long link: one
# bridge with three devices pressing 8 mm into a tissue block, the
# acupuncture scene and the cutting skin, every force model held back
# 0, 50, 100 and 200 ms (--model-delay-ms). The passivity observer must
# leave no violation uncorrected, and the watchdog's physics age must be the
# delay. Then the needle alone with its models 1000 ms late: over each
# insertion the rendering may not give the hand energy (work <= 0). check_passivity_under_delay.py prints the
# table and checks it.
set -euo pipefail
source "$(dirname "$0")/lib.sh" "$@"
start_server "t1:tissue_block,t2:acupuncture,t3:cutting" "${every_tick_server[@]}"
for delay in 0 50 100 200; do
  "$bin/hapsim-bridge" --device t1 --device t2 --device t3 --device-id 11 --dds-domain "$domain" "${every_tick_client[@]}" \
      --script insertion --depth-mm 8 --speed-mm-s 20 --hold-s 0.5 --seconds 2.5 --keep-running \
      --model-delay-ms "$delay" >"delay_$delay.out" 2>"delay_$delay.log"
done
# The needle with every model 1000 ms late, two insertion cycles (approach 2 mm, press 12 mm through
# skin and fat, hold 0.5 s, withdraw: 3.3 s each), traced: the work the rendering did on the hand.
"$bin/hapsim-bridge" --session t2 --device-id 21 --dds-domain "$domain" "${every_tick_client[@]}" --script insertion --depth-mm 12 \
    --speed-mm-s 10 --hold-s 0.5 --start-height-mm 2 --seconds 6.7 --keep-running --model-delay-ms 1000 \
    --trace needle_1000.csv >needle_1000.out 2>needle_1000.log
stop_process server_rc "$server"
pids=()
[ "$server_rc" = 0 ] || { echo "server exited with $server_rc"; cat server.log; exit 1; }
/usr/bin/python3 "$here/check_passivity_under_delay.py" "$work"
