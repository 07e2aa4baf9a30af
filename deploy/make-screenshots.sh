#!/usr/bin/env bash
# Makes the README's pictures of the viewer (drawn off screen, no display
# needed) from live runs on loopback:
#   OUT/viewer-acupuncture.png   one trainee's needle in the acupuncture scene, with the panels
#   OUT/viewer-force-depth.png   its force vs time and force vs depth plots
#   OUT/class-console.png        the instructor's class console of 6 trainees (tokens, TLS)
#   OUT/viewer-cutting.png       a 20 mm incision, the wound gaping (topology edits)
#   OUT/viewer-vessel.png        a probe pressing the dorsal vein 2 mm
# Usage: deploy/make-screenshots.sh [BUILD_DIR] [OUT_DIR]   (defaults: build, docs)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bin=$(cd "${1:-$root/build}" && pwd)/bin
out=$(mkdir -p "${2:-$root/docs}" && cd "${2:-$root/docs}" && pwd)
work=$(mktemp -d /tmp/hapsim-shots.XXXXXX)
pids=()
cleanup() { for p in "${pids[@]}"; do kill -KILL "$p" 2>/dev/null || true; done; rm -rf "$work"; }
trap cleanup EXIT
cd "$work"
domain=$((150 + RANDOM % 60))
start_server() {
  rm -f port
  "$bin/hapsim-server" --listen 127.0.0.1:0 --port-file port --dds-domain "$domain" "$@" >server.out 2>server.log &
  server=$!; pids+=("$server")
  for _ in $(seq 1 100); do [ -s port ] && break; sleep 0.1; done
  addr=127.0.0.1:$(cat port)
}

# 1. One trainee: repeated insertions to 12 mm through skin, fat and muscle.
start_server --sessions acu:acupuncture
"$bin/hapsim-bridge" --session acu --dds-domain "$domain" --script insertion --start-height-mm 2 \
    --depth-mm 12 --speed-mm-s 6 --hold-s 0.4 --entry-x-mm 0 >bridge.out 2>bridge.log &
pids+=($!)
sleep 0.5
"$bin/hapsim-viewer" --headless --server "$addr" --session acu --seconds 7.8 --size 1280x720 \
    --camera 0,0,-0.005,0.075,-30,22 --png "$out/viewer-acupuncture.png" --plot-png "$out/viewer-force-depth.png" \
    >viewer.out
kill -TERM "${pids[@]}" 2>/dev/null || true; wait 2>/dev/null || true; pids=()

# 2. A cut and a vessel press, side by side on one server.
start_server --sessions c:cutting,v:vessel
"$bin/hapsim-bridge" --session c --dds-domain "$domain" --script cut --start-height-mm 5 --depth-mm 1.5 \
    --speed-mm-s 10 --entry-x-mm -10 --cut-length-mm 20 --keep-running >cut.out 2>&1 &
pids+=($!)
"$bin/hapsim-bridge" --session v --dds-domain "$domain" --script insertion --start-height-mm 3 --depth-mm 2 \
    --speed-mm-s 5 --hold-s 30 >vessel.out 2>&1 &
pids+=($!)
sleep 5
"$bin/hapsim-viewer" --headless --server "$addr" --session c --seconds 1.5 --size 960x540 --panels=false \
    --camera 0,0,0,0.06,-25,40 --png "$out/viewer-cutting.png" >>viewer.out
"$bin/hapsim-viewer" --headless --server "$addr" --session v --seconds 1.5 --size 960x540 --panels=false \
    --png "$out/viewer-vessel.png" >>viewer.out
kill -TERM "${pids[@]}" 2>/dev/null || true; wait 2>/dev/null || true; pids=()

# 3. A class of 6 with tokens and TLS, driven by the load generator.
bash "$root/deploy/make-dev-certs.sh" certs >/dev/null
bash "$root/deploy/make-class.sh" class acu-101 6 acupuncture 10 >/dev/null
start_server --class-config class/class.toml --tls-cert certs/server.pem --tls-key certs/server.key
"$bin/hapsim-load" --sessions t1,t2,t3,t4,t5,t6 --dds-domain "$domain" --script insertion --depth-mm 12 \
    --speed-mm-s 10 --hold-s 0.3 --phase-spread-s 1.5 --seconds 12 >load.out 2>load.err &
pids+=($!)
sleep 1
"$bin/hapsim-viewer" --headless --server "$addr" --tls-ca certs/ca.pem --token-file class/tokens/instructor.token \
    --class acu-101 --session t3 --seconds 6 --size 1600x900 --camera 0,0,-0.005,0.075,-30,22 \
    --png "$out/class-console.png" >console.out
kill -TERM "${pids[@]}" 2>/dev/null || true; wait 2>/dev/null || true; pids=()
cat viewer.out console.out
echo "pictures in $out"
