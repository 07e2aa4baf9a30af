#!/usr/bin/env bash
# What the browser console costs the server, and whether it disturbs the
# 1 kHz loop (not in CI: run by hand on a quiet 2-core machine; figures in
# docs/performance.md, "The web console"). A class of TRAINEES acupuncture
# sessions on TLS with tokens; hapsim-server pinned to core 0 with one tick
# worker; hapsim-load on core 1 driving every trainee (needle insertions,
# its devices on their own clocks); for each N in BROWSERS, N console
# connections (bench_web_probe, core 1) watch the class at 10 Hz as the
# tiles do, the first also viewing t1 and acknowledging every frame. Each N
# is a fresh server, run back to back. Then, for each N in NATIVE, N native
# consoles side by side (what hapsim-viewer --class does: each a gRPC
# channel with its own WatchClass stream, the first also viewing t1; the
# server serves at most 16 WatchClass streams). Reports: server CPU [cores], the
# round trip p50/p99 and the server's late ticks (hapsim-load's report),
# class status sizes, and the view's frame rate and frame sizes. Then one
# more run with a real browser (Debian's Chromium, web/bench/view_lag.mjs)
# viewing t1 (only t1's device streams, so core 1 is mostly the browser's),
# unthrottled and then with its CPU throttled THROTTLE times (DevTools'
# CPU throttling): drawings per second and how far the view lags behind.
#
#   tests/bench/web_console.sh [BIN_DIR] [OUT_DIR]
#
# Environment: BROWSERS [0 1 30 0 30], NATIVE [16], TRAINEES [16], RUN_S [10], THROTTLE
# [4 10] (empty: no browser run), PROBE_NICE [19], SERVER_FLAGS [], WEB_NICE
# [] (the console thread's nice, set with renice once the server runs;
# empty: as the server sets it, 10), SERVER_CPUS [0] (the server's taskset;
# e.g. 0,1 with SERVER_FLAGS="--tick-cpus 0"). All on 127.0.0.1.
set -euo pipefail
repo=$(cd "$(dirname "$0")/../.." && pwd)
bin=$(cd "${1:-$repo/build/bin}" && pwd)
out=${2:-$repo/build/web-console-$(date -u +%Y%m%dT%H%M%SZ)}
BROWSERS=${BROWSERS:-0 1 30 0 30}
NATIVE=${NATIVE-16}
THROTTLE=${THROTTLE-4 10}
# The browsers are other machines; here they share core 1 with the trainees'
# devices, so by default they yield to them (0: compete as equals).
PROBE_NICE=${PROBE_NICE:-19}
SERVER_FLAGS=${SERVER_FLAGS:-}  # e.g. "--rt-priority 40": the tick worker above the console's threads
TRAINEES=${TRAINEES:-16}
RUN_S=${RUN_S:-10}
mkdir -p "$out" && cd "$out"
pids=()
cleanup() { for p in "${pids[@]}"; do kill -KILL "$p" 2>/dev/null || true; done; }
trap cleanup EXIT
cpu_ticks() { awk '{ print $14 + $15 }' "/proc/$1/stat"; }
free_port() { /usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }
bash "$repo/deploy/make-dev-certs.sh" certs >/dev/null
bash "$repo/deploy/make-class.sh" class bench "$TRAINEES" acupuncture >/dev/null
sessions=$(seq -s, -f 't%g' 1 "$TRAINEES")
hz=$(getconf CLK_TCK)

# start_class SECONDS SESSIONS: a fresh server (core 0) and these trainees' devices (core 1) in the current folder.
start_class() {
  domain=$((220 + RANDOM % 12)) grpc_port=$(free_port) web_port=$(free_port)
  taskset -c "${SERVER_CPUS:-0}" "$bin/hapsim-server" --listen "127.0.0.1:$grpc_port" --dds-domain "$domain" --workers 1 \
      --class-config "$out/class/class.toml" --tls-cert "$out/certs/server.pem" --tls-key "$out/certs/server.key" \
      --web-listen "127.0.0.1:$web_port" $SERVER_FLAGS >server.out 2>server.log &
  server=$!; pids+=("$server")
  for _ in $(seq 1 100); do grep -q "web console at" server.log && break; sleep 0.1; done
  if [ -n "${WEB_NICE:-}" ]; then
    for task in /proc/"$server"/task/*; do
      [ "$(cat "$task/comm")" = hapsim-web ] && renice -n "$WEB_NICE" -p "${task##*/}" >/dev/null
    done
  fi
  taskset -c "${load_core:-1}" "$bin/hapsim-load" --sessions "$2" --dds-domain "$domain" --script insertion \
      --seconds "$1" --server "127.0.0.1:$grpc_port" --tls-ca "$out/certs/ca.pem" \
      --token-file "$out/class/tokens/instructor.token" --server-stats --json load.json ${load_flags:-} \
      >load.out 2>load.err &
  load=$!; pids+=("$load")
  sleep 2
}

k=0
runs=()
for run in $(for n in $BROWSERS; do echo "browsers-$n"; done; for n in $NATIVE; do echo "native-$n"; done); do
  n=${run##*-}
  k=$((k + 1)) dir="$out/run-$k-$run" && mkdir -p "$dir" && cd "$dir"
  runs+=("run-$k-$run")
  start_class $((RUN_S + 4)) "$sessions"
  before=$(cpu_ticks "$server")
  if [ "$n" -gt 0 ]; then
    if [ "${run%-*}" = native ]; then to=(--grpc "127.0.0.1:$grpc_port"); else to=(--port "$web_port"); fi
    taskset -c 1 nice -n "$PROBE_NICE" "$bin/bench_web_probe" "${to[@]}" --tls-ca "$out/certs/ca.pem" \
        --token-file "$out/class/tokens/observer.token" --class bench --view t1 --clients "$n" \
        --seconds "$RUN_S" >probe.json 2>probe.err || true
  else
    sleep "$RUN_S"
  fi
  after=$(cpu_ticks "$server")
  wait "$load" || true
  kill -TERM "$server"; wait "$server" || true
  echo "{\"consoles\": $n, \"server_cores\": $(awk -v a="$before" -v b="$after" -v hz="$hz" -v s="$RUN_S" \
      'BEGIN { printf "%.3f", (b - a) / hz / s }')}" >cpu.json
  cd "$out"
done
/usr/bin/python3 - "$out" "${runs[@]}" <<'PY'
import json, sys, os
out, runs = sys.argv[1], sys.argv[2:]
print(f"{'consoles':>11} {'server cores':>12} {'rt p50 ms':>9} {'rt p99 ms':>9} {'late ticks':>10} "
      f"{'status B':>8} {'max':>6} {'view fps':>8} {'vertices':>8} {'key B':>7} {'delta B':>7} {'max':>6}")
for run in runs:
    kind, n = run.split("-")[-2:]
    n = f"{n} {'web' if kind == 'browsers' else 'native'}"
    d = os.path.join(out, run)
    cpu = json.load(open(os.path.join(d, "cpu.json")))
    load = json.load(open(os.path.join(d, "load.json")))
    probe = json.load(open(os.path.join(d, "probe.json"))) if os.path.exists(os.path.join(d, "probe.json")) else {}
    late = sum(s["late_ticks"] for s in load.get("server_sessions", []))
    rt = load["total"]["round_trip_ms"]
    g = lambda k: probe.get(k, 0)
    print(f"{n:>11} {cpu['server_cores']:>12.3f} {rt['p50']:>9.2f} {rt['p99']:>9.2f} {late:>10} "
          f"{g('status_bytes_mean'):>8.0f} {g('status_bytes_max'):>6} {g('view_fps'):>8.1f} {g('view_vertices'):>8} "
          f"{g('keyframe_bytes'):>7} {g('delta_bytes_mean'):>7.0f} {g('delta_bytes_max'):>6}")
PY

if [ -n "$THROTTLE" ]; then
  dir="$out/view-lag" && mkdir -p "$dir" && cd "$dir"
  # One device, on the server's core at the nominal rate: core 1 is the
  # browser's alone, as a laptop is not a load generator. (The lag is read
  # against each frame's server send time, so no device clock enters it.)
  load_core=0 load_flags="--clock-rate-ppm 0" start_class 60 t1
  spki=$(openssl x509 -in "$out/certs/server.pem" -pubkey -noout | openssl pkey -pubin -outform der |
         openssl dgst -sha256 -binary | base64)
  HAPSIM_WEB_URL="https://127.0.0.1:$web_port/" HAPSIM_WEB_SPKI="$spki" HAPSIM_TOKENS="$out/class/tokens" \
  HAPSIM_SESSION=t1 THROTTLE="$THROTTLE" taskset -c 1 node "$repo/web/bench/view_lag.mjs" >lag.json || true
  kill -TERM "$server"; wait "$server" || true
  /usr/bin/python3 - lag.json <<'PY'
import json, sys
cols = ["name", "fps", "lag_ms_p50", "lag_ms_p99", "lag_ms_max", "draw_ms_p50", "messages_per_s", "ms_per_message"]
print("browser view of t1: " + " ".join(cols))
for p in json.load(open(sys.argv[1])):
    if p.get("no_answer"):
        print(f"  {p['name']}: the page stopped answering the DevTools protocol")
        continue
    print("  " + " ".join(p[c] if isinstance(p[c], str) else f"{p[c]:.1f}" for c in cols))
PY
fi
