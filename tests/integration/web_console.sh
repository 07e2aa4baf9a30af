#!/usr/bin/env bash
# The class console in a real browser: a class of 4 acupuncture trainees on
# TLS with tokens (deploy/make-dev-certs.sh, deploy/make-class.sh), driven by
# hapsim-load, served to Debian's Chromium by hapsim-server --web-listen, and
# checked by web/test/console.test.mjs (playwright-core): a garbage token is
# refused, every tile appears and updates, a trainee's 3D view draws the
# needle where the tool pose projects, on an emulated tablet a tap opens a
# trainee and touch turns and zooms the view, an observer's reset is refused
# in the page and at the server, and the page reconnects after a server
# restart (and more: web/test/console.test.mjs); then the same page in
# Firefox (web/test/firefox.test.mjs, on a virtual X display).
# Chromium trusts exactly the server's certificate (its SPKI hash).
# Bounded (about 60 s); everything on 127.0.0.1.
set -euo pipefail
source "$(dirname "$0")/lib.sh" "$@"
repo=$(cd "$here/../.." && pwd)
bash "$repo/deploy/make-dev-certs.sh" certs >/dev/null
bash "$repo/deploy/make-class.sh" class web-101 4 acupuncture 10 >/dev/null
free_port() { /usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }
grpc_port=$(free_port) web_port=$(free_port)
server_flags=(--class-config class/class.toml --tls-cert certs/server.pem --tls-key certs/server.key
              --web-listen "127.0.0.1:$web_port")
start_web_server() {
  "$bin/hapsim-server" --listen "127.0.0.1:$grpc_port" --dds-domain "$domain" "${server_flags[@]}" \
      >>server.out 2>>server.log &
  echo $! >server.pid
  for _ in $(seq 1 100); do grep -q "web console at" server.log 2>/dev/null && return 0; sleep 0.1; done
  echo "server did not start"; cat server.log; exit 1
}
start_web_server
pids+=("$(cat server.pid)")
# The restart the page must survive: same ports, the class's sessions anew.
cat >restart.sh <<RESTART
set -e
cd "$work"
kill -TERM "\$(cat server.pid)"; while kill -0 "\$(cat server.pid)" 2>/dev/null; do sleep 0.05; done
: >server.log.restart; mv server.log server.log.first
$(declare -f start_web_server)
$(declare -p bin domain grpc_port server_flags)
start_web_server
RESTART
"$bin/hapsim-load" --sessions t1,t2,t3,t4 --dds-domain "$domain" --script insertion \
    --depth-mm 12 --speed-mm-s 10 --hold-s 0.5 --phase-spread-s 1.0 --seconds 120 >load.out 2>load.err &
pids+=($!)
spki=$(openssl x509 -in certs/server.pem -pubkey -noout | openssl pkey -pubin -outform der |
       openssl dgst -sha256 -binary | base64)
mkdir -p shots
# Firefox gets a window on a virtual display of its own (Xvfb picks a free number).
Xvfb -displayfd 3 -screen 0 1366x768x24 -nolisten tcp 3>xvfb.display 2>xvfb.log &
pids+=($!)
for _ in $(seq 1 50); do [ -s xvfb.display ] && break; sleep 0.1; done
[ -s xvfb.display ] || { echo "Xvfb did not start"; cat xvfb.log; exit 1; }
export HAPSIM_WEB_URL="https://127.0.0.1:$web_port/" HAPSIM_WEB_SPKI="$spki" HAPSIM_TOKENS="$work/class/tokens" \
       HAPSIM_SESSIONS=t1,t2,t3,t4 HAPSIM_RESTART="bash $work/restart.sh" HAPSIM_SHOTS="$work/shots"
code=0
timeout 120 node --test --test-reporter=spec "$repo/web/test/console.test.mjs" || code=$?
[ -f server.pid ] && pids+=("$(cat server.pid)")
DISPLAY=":$(cat xvfb.display)" timeout 90 node --test --test-reporter=spec "$repo/web/test/firefox.test.mjs" || code=$?
grep -c "web console: connection refused" server.log* || true
exit "$code"
