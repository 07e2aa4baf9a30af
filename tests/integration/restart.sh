#!/usr/bin/env bash
# Nothing a class did is lost when its server dies: a class of 3 acupuncture
# trainees (tokens, TLS) on a server with a data directory; hapsim-load drives
# all three; the instructor resets t1 (ending its first trial) and scores it;
# then the server is killed with SIGKILL mid-insertion and started again on
# the same directory. check_restart.py checks:
#  - the sessions came back (the log says so; t1..t3 listed) and went on from
#    their recorded state: sim time after the restart >= what the recording
#    reached, and the recording lost <= 100 ms of the trial before the kill;
#  - the devices drove them again (ticks and poses after the restart);
#  - the trials (t1's ended trial 0 with its depth) and the scores came back
#    from the database, identical to before the kill;
#  - the recordings are listed, fetched over gRPC, and every one replays with
#    hapsim-replay to every recorded state hash — t1's second trial across the
#    kill (a resume mark in it) included, and again under glibc's other math
#    paths (as on another CPU); a trainee sees only its own, an
#    observer cannot delete, a running trial's recording cannot be deleted,
#    an ended one can.
# Bounded (about 25 s); everything on 127.0.0.1.
set -euo pipefail
source "$(dirname "$0")/lib.sh" "$@"
repo=$(cd "$here/../.." && pwd)
bash "$repo/deploy/make-dev-certs.sh" certs >/dev/null
bash "$repo/deploy/make-class.sh" class acu-201 3 acupuncture 10 >/dev/null
server_flags=(--class-config class/class.toml --tls-cert certs/server.pem --tls-key certs/server.key
              --data-dir data --checkpoint-every-s 0.5)
tls=(--tls-ca certs/ca.pem)
as() { local who=$1; shift; "$bin/hapsim-ctl" --server "$addr" "${tls[@]}" --token-file "class/tokens/$who.token" "$@"; }
run() { local name=$1 code=0; shift; "$@" >"$name.out" 2>"$name.err" || code=$?; echo "$code" >"$name.rc"; }

start_server "" "${server_flags[@]}"
cp server.log server1_start.log
# The devices: 3 synthetic needles for 14 s (they outlive the first server and reconnect to the second).
"$bin/hapsim-load" --sessions t1,t2,t3 --dds-domain "$domain" --script insertion --depth-mm 12 --speed-mm-s 20 \
    --hold-s 0.3 --phase-spread-s 1.0 --seconds 14 >load.out 2>load.err &
load=$!; pids+=("$load")
sleep 2
run reset_t1 as instructor reset t1
run score1 as instructor score t1 --expert dr-a --indicators 8,6,7,9,5,8,7
run score2 as instructor score t1 --expert dr-b --indicators 6,6,9,9,7,8,5
sleep 2.5
run scores_before as instructor scores
run trials_before as instructor trials acu-201 --csv trials_before.csv
date +%s.%N >info_start_time
run info_before as instructor info t2
date +%s.%N >info_end_time
date +%s.%N >kill_time
kill -KILL "$server"
wait "$server" 2>/dev/null || true
pids=("$load")
cp -r data data_after_kill  # what a crash leaves on disk, before the next server touches it
mv server.log server1.log

sleep 0.5
start_server "" "${server_flags[@]}"
date +%s.%N >restart_time
sleep 0.3
run info_t2_early as instructor info t2
sleep 3
run list_after as instructor list
run info_after as instructor info t2
run scores_after as instructor scores
run trials_after as instructor trials acu-201 --csv trials_after.csv
run recordings as instructor recordings
run recordings_trainee2 as trainee2 recordings
run recordings_other as trainee2 recordings t1
run observer_delete as observer delete-recording "$(awk '$2 == "t1" && $3 == "0" {print $1}' recordings.out)"
run delete_running as instructor delete-recording "$(awk '$2 == "t2" && $NF == "open" {print $1; exit}' recordings.out)"
# Replays in the server: t1's ended trial 0 at 4x, watched by its trainee;
# t2's trial paused, stepped, sought forward and back (from a kept state).
t1_0=$(awk '$2 == "t1" && $3 == "0" {print $1}' recordings.out)
t2_0=$(awk '$2 == "t2" {print $1; exit}' recordings.out)
run play_open as trainee1 replay "$t1_0" --speed 4
replay_id=$(awk 'NR == 1 {print $1}' play_open.out)
"$bin/hapsim-viewer" --headless --server "$addr" "${tls[@]}" --token-file class/tokens/trainee1.token \
    --session "$replay_id" --seconds 1.5 >play_viewer.out 2>play_viewer.err && echo 0 >play_viewer.rc || echo $? >play_viewer.rc
run play_done as trainee1 replay-info "$replay_id"
run play_other as trainee2 replay-info "$replay_id"
run play_paused as instructor replay "$t2_0" --paused
paused_id=$(awk 'NR == 1 {print $1}' play_paused.out)
run play_step as instructor step "$paused_id" --ticks 500
sleep 1.0  # one step per tick: 0.5 s at 1x
run play_stepped as instructor replay-info "$paused_id"
run play_seek as instructor seek "$paused_id" --to-s 2.0
sleep 0.3
run play_sought as instructor replay-info "$paused_id"
# Back to 1.2 s: from the state kept at a checkpoint the first seek passed;
# then 600 ticks on reach the next recorded hash (checkpoints every 0.5 s).
run play_back as instructor seek "$paused_id" --to-s 1.2
run play_back_step as instructor step "$paused_id" --ticks 600
sleep 1.0
run play_back_stepped as instructor replay-info "$paused_id"
run play_close as instructor close "$paused_id"
# The instructor's console opens t1's past trial 0 from its Past trials list
# (--open-trial takes the Open button's path) and watches it, off screen.
if grep -q -- "--png" <<<"$("$bin/hapsim-viewer" --help)"; then
  "$bin/hapsim-viewer" --headless --server "$addr" "${tls[@]}" --token-file class/tokens/instructor.token \
      --class acu-201 --open-trial "$t1_0" --seconds 3 --size 1280x720 --png past_trial.png \
      >console_past.out 2>console_past.err && echo 0 >console_past.rc || echo $? >console_past.rc
  console_replay=$(sed -n 's/^viewer: session \(replay-[0-9]*\),.*/\1/p' console_past.out)
  run console_replay_closed as instructor replay-info "${console_replay:-none}"
fi
mkdir -p fetched
while read -r id session trial _; do
  [ "$id" = id ] && continue
  run "fetch_${session}_$trial" as instructor fetch-recording "$id" --output "fetched/${session}_t$trial.hrec"
done <recordings.out
wait "$load" || true
stop_process server_rc "$server"
pids=()
mv server.log server2.log
# Every recording on disk replays to its hashes (the fetched copies are of running trials: read to where they were).
for f in data/recordings/*/*.hrec fetched/*.hrec data_after_kill/recordings/*/*.hrec; do
  name=$(echo "$f" | tr '/' '_')
  run "replay_$name" "$bin/hapsim-replay" "$f"
  # As on a CPU without AVX2/FMA (glibc's other math paths): the same hashes.
  run "otherlibm_$name" env GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA "$bin/hapsim-replay" "$f"
done
# Deleting an ended trial's recording works once its trial is over (server 3, no devices).
start_server "" "${server_flags[@]}"
run delete_t1_0 as instructor delete-recording "$(awk '$2 == "t1" && $3 == "0" {print $1}' recordings.out)"
run recordings_final as instructor recordings
stop_process server3_rc "$server"
pids=()
/usr/bin/python3 "$here/check_restart.py" "$work" "$server_rc"
