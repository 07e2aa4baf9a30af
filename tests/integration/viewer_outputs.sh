#!/usr/bin/env bash
# Every output flag of hapsim-viewer works with every other, and pictures
# asked for without a display are drawn off screen:
#  1. no display, a recording: --png, --plot-png, --obj and --export at once;
#  2. no display, a live session, no --headless: --png and --obj;
#  3. --headless, a live session: --record, --png and --export, and the
#     recording replays into the same mesh;
#  4. a counting viewer over the whole session: the peak force its frames
#     carry is the server's 1 kHz peak (the skin's brief puncture peak), not
#     the force at the frames' 60 Hz ticks.
# check_viewer_outputs.py reads the files.
set -euo pipefail
source "$(dirname "$0")/lib.sh" "$@"
recording="$here/../viewer-gui/data/acupuncture.frames"
nodisplay=(env -u DISPLAY -u WAYLAND_DISPLAY)
"${nodisplay[@]}" "$bin/hapsim-viewer" --replay "$recording" --size 320x240 --png replay.png \
    --plot-png replay_plot.png --obj replay.obj --export replay.glb >replay.out 2>replay.log

start_server "out:acupuncture"
"$bin/hapsim-viewer" --headless --server "$addr" --session out --seconds 5.5 >counting.out 2>counting.log &
counting=$!; pids+=("$counting")
sleep 0.5
"$bin/hapsim-bridge" --session out --dds-domain "$domain" --script insertion --start-height-mm 1 --depth-mm 4 \
    --speed-mm-s 10 --hold-s 0.2 --seconds 4 >bridge.out 2>bridge.log &
pids+=("$!")
sleep 0.5
"${nodisplay[@]}" "$bin/hapsim-viewer" --server "$addr" --session out --seconds 1.5 --size 320x240 \
    --png live.png --obj live.obj >live.out 2>live.log
"$bin/hapsim-viewer" --headless --server "$addr" --session out --seconds 1.5 --size 320x240 --record live.frames \
    --png recorded.png --export recorded.vtk >recorded.out 2>recorded.log
"${nodisplay[@]}" "$bin/hapsim-viewer" --replay live.frames --size 320x240 --obj replayed.obj \
    >replayed.out 2>replayed.log
wait "$counting"
"$bin/hapsim-ctl" --server "$addr" info out >info.txt
stop_process server_rc "$server"
pids=()
/usr/bin/python3 "$here/check_viewer_outputs.py" "$work"
