#!/usr/bin/env bash
# A site of two servers behind one directory, in the network lab: servers
# "srva" (class lab-a: sessions a1, a2) and "srvb" (class lab-b: b1, b2) on
# two hosts, each with its own class config and tokens, TLS with one site
# CA, and the same directory (site.toml). From a third host, trainees ask
# the server that does NOT run their session: hapsim-ctl locate, a viewer
# and a bridge (--join) find it on the other server and use it there. Then
# srvb is killed: its sessions are reported unavailable (naming srvb), while
# a1's bridge and viewer — which found a1 through srvb — run on to their end.
# check_netlab_two_servers.py reads the results. Exits 77 (skipped) where
# namespaces cannot be made.
set -euo pipefail
source "$(dirname "$0")/lib.sh" "$@"
source "$here/netlab_lib.sh"
lab_up ts --seconds 90 --realtime srva srvb client=delay_ms=2
"$repo/deploy/make-dds-config.sh" --interface hl0 --peer 10.77.0.1 --peer 10.77.0.2 --peer 10.77.0.3 \
    --out dds.xml
on() { "$netlab" exec "$lab" "$@"; }

bash "$repo/deploy/make-dev-certs.sh" certs 10.77.0.1 10.77.0.2 >/dev/null
# Two classes, session ids unique on the site (make-class names them t1, t2).
for c in a b; do
  bash "$repo/deploy/make-class.sh" "class_$c" "lab-$c" 2 tissue_block >/dev/null
  sed -i "s/\"t\([0-9]\)\"/\"$c\1\"/g" "class_$c/class.toml"
done
cat >site.toml <<'TOML'
[[server]]
name = "srva"
address = "10.77.0.1:50051"
[[server]]
name = "srvb"
address = "10.77.0.2:50051"
TOML
serve() {  # HOST IP CLASS_DIR
  on_bg "$1" "$bin/hapsim-server" --listen "$2:50051" --class-config "$3/class.toml" \
      --tls-cert certs/server.pem --tls-key certs/server.key --dds-config dds.xml \
      --directory site.toml --server-name "$1" --peer-tls-ca certs/ca.pem --peer-timeout-ms 500 \
      >"$1.out" 2>"$1.log"
}
serve srva 10.77.0.1 class_a
server_a=$!; pids+=("$server_a")
serve srvb 10.77.0.2 class_b
server_b=$!; pids+=("$server_b")
tls=(--tls-ca certs/ca.pem)
ctl() {  # NAME SERVER_IP TOKEN_FILE COMMAND...: hapsim-ctl on the client host -> NAME.out/.err/.rc
  local name=$1 ip=$2 token=$3; shift 3
  on client "$bin/hapsim-ctl" --server "$ip:50051" "${tls[@]}" --token-file "$token" "$@" \
      >"$name.out" 2>"$name.err" && echo 0 >"$name.rc" || echo $? >"$name.rc"
}
a1_token=class_a/tokens/trainee1.token b1_token=class_b/tokens/trainee1.token
# Wait for both servers (gRPC health through the lab).
for ip in 10.77.0.1 10.77.0.2; do
  for _ in $(seq 50); do
    on client "$bin/hapsim-ctl" --server "$ip:50051" "${tls[@]}" --timeout-s 1 health >/dev/null 2>&1 && break
    sleep 0.2
  done
done

# Each trainee asks the server that does not run its session.
ctl locate_b1 10.77.0.1 "$b1_token" locate b1
ctl locate_a1 10.77.0.2 "$a1_token" locate a1
ctl locate_b1_wrong_token 10.77.0.1 "$a1_token" locate b1
# a1: a bridge and a viewer that find it through srvb, running across srvb's death.
on_bg client "$bin/hapsim-bridge" --session a1 --join 10.77.0.2:50051 "${tls[@]}" --token-file "$a1_token" \
    --dds-config dds.xml --script insertion --depth-mm 4 --speed-mm-s 10 --hold-s 30 --start-height-mm 2 \
    --seconds 9 >bridge_a1.out 2>bridge_a1.log
bridge_a1=$!; pids+=("$bridge_a1")
on_bg client "$bin/hapsim-viewer" --headless --server 10.77.0.2:50051 --session a1 --seconds 8 "${tls[@]}" \
    --token-file "$a1_token" >viewer_a1.out 2>viewer_a1.log
viewer_a1=$!; pids+=("$viewer_a1")
# b1: the same through srva, ending before srvb dies.
on_bg client "$bin/hapsim-bridge" --session b1 --join 10.77.0.1:50051 "${tls[@]}" --token-file "$b1_token" \
    --dds-config dds.xml --script insertion --depth-mm 4 --speed-mm-s 10 --hold-s 0.5 --start-height-mm 2 \
    --seconds 2.5 >bridge_b1.out 2>bridge_b1.log
bridge_b1=$!; pids+=("$bridge_b1")
on client "$bin/hapsim-viewer" --headless --server 10.77.0.1:50051 --session b1 --seconds 2.5 "${tls[@]}" \
    --token-file "$b1_token" >viewer_b1.out 2>viewer_b1.log && echo 0 >viewer_b1.rc || echo $? >viewer_b1.rc
wait "$bridge_b1" && echo 0 >bridge_b1.rc || echo $? >bridge_b1.rc
ctl info_b1 10.77.0.1 "$b1_token" info b1       # followed to srvb: b1's counters
ctl info_a1_before 10.77.0.1 "$a1_token" info a1

# srvb dies (no clean shutdown), a1's devices still running.
kill -KILL "$server_b"; wait "$server_b" 2>/dev/null || true
date +%s.%N >killed_at
sleep 0.5
ctl locate_b1_after 10.77.0.1 "$b1_token" locate b1
ctl info_b1_after 10.77.0.1 "$b1_token" info b1
on client "$bin/hapsim-viewer" --headless --server 10.77.0.1:50051 --session b1 --seconds 2 "${tls[@]}" \
    --token-file "$b1_token" >viewer_b1_after.out 2>viewer_b1_after.log \
    && echo 0 >viewer_b1_after.rc || echo $? >viewer_b1_after.rc
ctl locate_a1_after 10.77.0.1 "$a1_token" locate a1
wait "$viewer_a1" && echo 0 >viewer_a1.rc || echo $? >viewer_a1.rc
wait "$bridge_a1" && echo 0 >bridge_a1.rc || echo $? >bridge_a1.rc
ctl info_a1_after 10.77.0.1 "$a1_token" info a1
stop_process server_a_rc "$server_a"
echo "$server_a_rc" >server_a.rc
"$netlab" down "$lab"
for f in locate_b1 locate_a1 locate_b1_after locate_a1_after; do echo "== $f"; cat "$f.out" "$f.err"; done
cat bridge_b1.out bridge_a1.out viewer_b1.out viewer_a1.out
/usr/bin/python3 "$here/check_netlab_two_servers.py" "$work"
