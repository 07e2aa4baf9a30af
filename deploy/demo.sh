#!/usr/bin/env bash
# One command, fresh Debian 12 machine: install dependencies, build, then run
# the whole chain on loopback for about 10 s — physics server, a synthetic
# device-bridge doing needle insertions, a headless viewer — and print a
# short summary. Environment: DEMO_SECONDS (default 10), DEMO_SCENE
# (default tissue_block; see `build/bin/hapsim-ctl scenes`), DEMO_DDS_DOMAIN
# (default: one picked at random in 100-149, so two demos, or a demo beside a
# server on the default domain 0, do not share a domain; the summary prints it).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=${DEMO_SECONDS:-10}
scene=${DEMO_SCENE:-tissue_block}
domain=${DEMO_DDS_DOMAIN:-$((100 + RANDOM % 50))}
case "$domain" in
  ''|*[!0-9]*) echo "demo: DEMO_DDS_DOMAIN must be a number in 0-232, not '$domain'" >&2; exit 2 ;;
esac
[ "$domain" -le 232 ] || { echo "demo: DEMO_DDS_DOMAIN must be in 0-232 (DDS's limit), not $domain" >&2; exit 2; }
"$root/deploy/install-deps.sh"
"$root/deploy/build.sh"
bin="$root/build/bin"
out=$(mktemp -d /tmp/hapsim-demo.XXXXXX)
pids=()
cleanup() { for p in "${pids[@]}"; do kill -KILL "$p" 2>/dev/null || true; done; }
trap cleanup EXIT

echo "demo: starting server, device-bridge and viewer on 127.0.0.1 for ${seconds} s (scene ${scene}, DDS domain ${domain})"
"$bin/hapsim-server" --listen 127.0.0.1:0 --port-file "$out/port" --sessions "demo:$scene" --dds-domain "$domain" \
    >"$out/server.out" 2>"$out/server.log" &
server=$!; pids+=("$server")
for _ in $(seq 1 100); do [ -s "$out/port" ] && break; sleep 0.1; done
[ -s "$out/port" ] || { echo "demo: the server did not start:"; cat "$out/server.log"; exit 1; }
addr=127.0.0.1:$(cat "$out/port")

"$bin/hapsim-viewer" --headless --server "$addr" --session demo --obj "$out/viewer.obj" \
    >"$out/viewer.out" 2>"$out/viewer.log" &
viewer=$!; pids+=("$viewer")
# A second viewer draws the last frame and its force plots off screen (EGL;
# no display needed) when it is stopped.
"$bin/hapsim-viewer" --headless --server "$addr" --session demo --png "$out/viewer.png" \
    --plot-png "$out/force.png" >"$out/picture.out" 2>"$out/picture.log" &
picture=$!; pids+=("$picture")
script_args=(--script insertion --start-height-mm 5 --depth-mm 5 --speed-mm-s 10 --hold-s 0.5)
[ "$scene" = acupuncture ] && script_args=(--script constant_speed --start-height-mm 2 --depth-mm 30 --speed-mm-s 20 --keep-running)
# A 20 mm incision along +x, 1.5 mm deep at 10 mm/s, then the blade waits above the wound.
[ "$scene" = cutting ] && script_args=(--script cut --start-height-mm 5 --depth-mm 1.5 --speed-mm-s 10 --entry-x-mm -10 --cut-length-mm 20 --keep-running)
# Probe the dorsal vein's crest 2 mm deep (of its 3.3 mm outer diameter) at 5 mm/s.
[ "$scene" = vessel ] && script_args=(--script insertion --start-height-mm 3 --depth-mm 2 --speed-mm-s 5 --hold-s 0.5)
"$bin/hapsim-bridge" --session demo --dds-domain "$domain" "${script_args[@]}" --seconds "$seconds" --trace "$out/trace.csv" \
    >"$out/bridge.out" 2>"$out/bridge.log" &
bridge=$!; pids+=("$bridge")
wait "$bridge"
sleep 0.3
"$bin/hapsim-ctl" --server "$addr" list >"$out/sessions.txt"
kill -TERM "$viewer" && wait "$viewer" || true
kill -TERM "$picture" && wait "$picture" || true
kill -TERM "$server" && wait "$server" || true
pids=()

field() { sed -n "s|.*$1.*|\\1|p" "$2" | head -n1; }
sessions=$(wc -l <"$out/sessions.txt")
ticks=$(field ' ticks=\([0-9]*\)' "$out/sessions.txt")
late=$(field 'late_ticks=\([0-9]*\)' "$out/sessions.txt")
poses=$(field 'poses_received=\([0-9]*\)' "$out/sessions.txt")
loop=$(field 'bridge: loop \([0-9.]* Hz\)' "$out/bridge.out")
rtt=$(field 'bridge: round trip \(p50 [0-9.]* / p99 [0-9.]*\) ' "$out/bridge.out")
models=$(field 'force models received \([0-9]*\)' "$out/bridge.out")
frames=$(field 'frames \([0-9]*\) (' "$out/viewer.out")
keyframes=$(field 'keyframes \([0-9]*\),' "$out/viewer.out")
bytes=$(field 'bytes \([0-9]*\),' "$out/viewer.out")
gaps=$(field 'gaps \([0-9]*\),' "$out/viewer.out")
events=$(field 'events:\(.*\)' "$out/viewer.out")
force=$(field 'bridge: force peak \([0-9.]* N\)' "$out/bridge.out")
physics_force=$(field 'peak_tool_force_n=\([0-9.]*\)' "$out/sessions.txt")
cuts=$(field 'viewer: \(frames with topology edits .*\)' "$out/viewer.out")

cat <<SUMMARY

hapsim demo summary (${seconds} s on loopback, scene ${scene}, DDS domain ${domain})
  sessions            ${sessions} (demo: ${ticks} ticks at 1 kHz, ${late} late ticks)
  pose rate           ${loop} from the bridge; ${poses} poses accepted by the server
  force-model RTT     ${rtt} ms (${models} models received by the bridge)
  viewer              ${frames} frames (${keyframes} keyframe), ${bytes} bytes, ${gaps} gaps; events:${events}
  peak contact force  ${force} rendered (clamp 2.5 N); physics peak ${physics_force} N
  files               ${out}/ (logs, trace.csv, viewer.obj, viewer.png, force.png)
SUMMARY
if [ -n "$cuts" ]; then echo "  cutting             ${cuts}"; fi
