#!/usr/bin/env bash
# The on-screen viewer under Xvfb: server + synthetic bridge +
# hapsim-viewer in a real GLFW window. Pictures before and during a press of
# the needle on the acupuncture skin (1.5 mm: a dimple, the skin punctures
# at ~2.6 mm) are checked by check_viewer_gui.py against the camera model
# written out in Python. Then the window lives through a malformed/lost
# frame (resync), the server killed -9 and restarted (reconnect) and its
# session closed under it (message), and still draws at the end.
set -euo pipefail
session=gui
source "$(dirname "$0")/lib.sh" "$@"
command -v Xvfb >/dev/null || { echo "Xvfb missing (deploy/install-deps.sh installs xvfb)"; exit 1; }

# A private X server; -displayfd tells us the display number it took.
Xvfb -displayfd 3 -screen 0 1024x768x24 -nolisten tcp 3>display.txt 2>xvfb.log &
xvfb=$!; pids+=("$xvfb")
for _ in $(seq 1 50); do [ -s display.txt ] && break; sleep 0.1; done
[ -s display.txt ] || { echo "Xvfb did not start"; cat xvfb.log; exit 1; }
export DISPLAY=":$(cat display.txt)"

start_server "$session:acupuncture"
port=${addr##*:}
camera="0.004,0.0,-0.002,0.06,-30,30,40"   # TX,TY,TZ,DISTANCE,YAW,PITCH,FOV (m, deg)
picture=(--size 640x480 --panels=false --camera "$camera")
bridge_common=(--session "$session" --dds-domain "$domain" --entry-x-mm 4 --entry-y-mm 0)

# 1. Before: the needle held 3 mm above the skin at (4, 0) mm.
"$bin/hapsim-bridge" "${bridge_common[@]}" --script hold --start-height-mm 3 >hold.out 2>hold.log &
bridge=$!; pids+=("$bridge")
sleep 1.5
"$bin/hapsim-viewer" --server "$addr" --session "$session" "${picture[@]}" --seconds 3 --png before.png \
    >before.out 2>before.log
# The tissue alone (no tool, no arrow), for the dimple comparison.
"$bin/hapsim-viewer" --server "$addr" --session "$session" "${picture[@]}" --show-tool=false --show-force=false \
    --seconds 2 --png before_tissue.png >before_tissue.out 2>&1
stop_process hold_rc "$bridge"

# 2. During a press: down to 1.5 mm at 5 mm/s and held there.
"$bin/hapsim-bridge" "${bridge_common[@]}" --script insertion --start-height-mm 1 --depth-mm 1.5 \
    --speed-mm-s 5 --hold-s 60 >press.out 2>press.log &
bridge=$!; pids+=("$bridge")
sleep 2
"$bin/hapsim-viewer" --server "$addr" --session "$session" "${picture[@]}" --seconds 3 --png after.png \
    >after.out 2>after.log
"$bin/hapsim-viewer" --server "$addr" --session "$session" "${picture[@]}" --show-tool=false --show-force=false \
    --seconds 2 --png after_tissue.png >after_tissue.out 2>&1
# The same moment with the panels, as people see it (kept as an artefact).
"$bin/hapsim-viewer" --server "$addr" --session "$session" --size 1280x720 --camera "$camera" --seconds 3 \
    --png panels.png >panels.out 2>panels.log

# Pacing: without vsync the window draws each new frame once, at most
# --max-fps (60), not flat out; a paused session (no new frames) is redrawn
# only at the idle rate (4 Hz).
"$bin/hapsim-viewer" --server "$addr" --session "$session" --size 640x480 --vsync=false --seconds 3 \
    >paced_live.out 2>paced_live.log
"$bin/hapsim-ctl" --server "$addr" pause "$session" >/dev/null
"$bin/hapsim-viewer" --server "$addr" --session "$session" --size 640x480 --vsync=false --seconds 3 \
    >paced_paused.out 2>paced_paused.log
"$bin/hapsim-ctl" --server "$addr" resume "$session" >/dev/null

# 3. Resilience: one window for ~16 s while the world misbehaves around it.
"$bin/hapsim-viewer" --server "$addr" --session "$session" --size 800x600 --seconds 16 --debug-drop-seq 20 \
    --png survived.png >survive.out 2>survive.log &
viewer=$!; pids+=("$viewer")
sleep 3
kill -KILL "$server"; wait "$server" 2>/dev/null || true
echo "server killed at +3 s"
sleep 2
"$bin/hapsim-server" --listen "127.0.0.1:$port" --sessions "$session:acupuncture" --dds-domain "$domain" \
    >server2.out 2>server2.log &
server=$!; pids+=("$server")
echo "server restarted at +5 s"
sleep 4
"$bin/hapsim-ctl" --server "$addr" close "$session" >close.out 2>&1
echo "session closed at +9 s"
sleep 2
kill -0 "$viewer" && echo "viewer alive after the close"
wait "$viewer" && viewer_rc=0 || viewer_rc=$?
stop_process bridge_rc "$bridge"
stop_process server_rc "$server"
stop_process xvfb_rc "$xvfb"
pids=()
echo "exit codes: viewer $viewer_rc, bridge $bridge_rc, server $server_rc"
cat before.out after.out survive.out close.out
grep -E "refused|lost|retrying" survive.log | head -5 || true
[ "$viewer_rc" -eq 0 ] && [ "$server_rc" -eq 0 ]
/usr/bin/python3 "$here/check_viewer_gui.py" "$work" "$camera"
