#!/usr/bin/env bash
# A class of 8 trainees on TLS with tokens, as README's classroom
# section runs it. deploy/make-dev-certs.sh and deploy/make-class.sh make
# the certificates and the class (8 acupuncture sessions t1..t8, tokens);
# hapsim-load drives all 8 with synthetic devices (phase-shifted needle
# insertions); the instructor watches with `hapsim-ctl watch`. check_classroom.py
# checks:
#  - the class view lists t1..t8, every one with its device streaming and
#    its own contact/puncture events, and tip depths > 0 while inserting;
#  - an observer may watch but not reset; a trainee may join its own session
#    but not view another's; no token and a plain-TCP client are refused;
#  - scores submitted by the instructor come back per session, and /metrics
#    counts the refusals (hapsim_auth_failures_total);
#  - the trials CSV: t1's trial ended by the reset went 12 mm deep (depth
#    error +2 mm against the 10 mm target), pierced skin, with peak forces
#    per layer; every session has a trial with punctures.
# Bounded (about 15 s); everything on 127.0.0.1.
set -euo pipefail
source "$(dirname "$0")/lib.sh" "$@"
repo=$(cd "$here/../.." && pwd)
bash "$repo/deploy/make-dev-certs.sh" certs >/dev/null
bash "$repo/deploy/make-class.sh" class acu-101 8 acupuncture 10 >/dev/null  # target depth 10 mm
rm -f metrics_port
start_server "" --class-config class/class.toml --tls-cert certs/server.pem --tls-key certs/server.key \
    --metrics-listen 127.0.0.1:0 --pose-timeout-ms 250
metrics_port=$(grep -o 'metrics at [^ ]* (port [0-9]*' server.log | grep -o '[0-9]*$' || true)
tls=(--server "$addr" --tls-ca certs/ca.pem)
ctl=("$bin/hapsim-ctl" "${tls[@]}")
as() { local who=$1; shift; "${ctl[@]}" --token-file "class/tokens/$who.token" "$@"; }
run() { local name=$1 code=0; shift; "$@" >"$name.out" 2>"$name.err" || code=$?; echo "$code" >"$name.rc"; }

# The trainees' devices: 8 synthetic needles, one per session, 7 s.
"$bin/hapsim-load" --sessions t1,t2,t3,t4,t5,t6,t7,t8 --dds-domain "$domain" --script insertion \
    --depth-mm 12 --speed-mm-s 20 --hold-s 0.3 --phase-spread-s 1.0 --seconds 7 >load.out 2>load.err &
load=$!; pids+=("$load")
# The instructor's live table (a pipe, so one block per update): 10 Hz for 6 s.
sleep 0.5
# The observer's class console, drawn off screen while the table runs.
console=""
if grep -q -- "--png" <<<"$("$bin/hapsim-viewer" --help)"; then
  "$bin/hapsim-viewer" --headless "${tls[@]}" --token-file class/tokens/observer.token --class acu-101 \
      --session t2 --seconds 4 --size 1280x720 --png console.png >console.out 2>console.err &
  console=$!; pids+=("$console")
  # Without --session: the console opens the class's first trainee (t1), with no refused call.
  "$bin/hapsim-viewer" --headless "${tls[@]}" --token-file class/tokens/observer.token --class acu-101 \
      --seconds 4 --size 640x360 --png console_first.png >console_first.out 2>console_first.err &
  console_first=$!; pids+=("$console_first")
fi
run watch as instructor watch acu-101 --rate-hz 10 --count 60
if [ -n "$console" ]; then
  wait "$console" && echo 0 >console.rc || echo $? >console.rc
  wait "$console_first" && echo 0 >console_first.rc || echo $? >console_first.rc
fi
run observer_watch as observer watch acu-101 --count 2
run observer_reset as observer reset t2
run trainee_join as trainee1 join t1
run trainee_other as trainee1 info t2
run no_token "${ctl[@]}" list
run plain_tcp "$bin/hapsim-ctl" --server "$addr" --token-file class/tokens/instructor.token list
run score1 as instructor score t1 --expert dr-a --indicators 8,6,7,9,5,8,7
run score2 as instructor score t1 --expert dr-b --indicators 6,6,9,9,7,8,5
run scores as instructor scores
wait "$load" || true
# The instructor ends t1's trial (reset) and exports the class's trials.
run reset_t1 as instructor reset t1
sleep 0.2
run trials as instructor trials acu-101 --csv trials.csv
run observer_trials as observer trials acu-101
curl -s "http://127.0.0.1:$metrics_port/metrics" >metrics.txt || true
stop_process server_rc "$server"
pids=()
tail -n 12 watch.out
/usr/bin/python3 "$here/check_classroom.py" "$work" "$server_rc"
