# Shared by the end-to-end scripts. Source it with the script's arguments
# (BIN_DIR WORK_DIR): it sets $bin, $work, $here, starts from an empty work
# directory, picks a test-only DDS domain and kills leftovers on exit. Then:
#   start_server SESSIONS [more server flags]   -> sets $addr, $server
bin=${1:?usage: $0 BIN_DIR WORK_DIR}
work=${2:?usage: $0 BIN_DIR WORK_DIR}
here=$(cd "$(dirname "$0")" && pwd)
rm -rf "$work" && mkdir -p "$work" && cd "$work"
# A DDS domain no other test process uses: the first free one of 20..219,
# claimed by an exclusive lock held while this script (and what it starts)
# runs — the same lock files as the C++ tests' (tests/test_dds_domain.h).
claim_domain() {
  local start=$((RANDOM % 200)) i d
  for i in $(seq 0 199); do
    d=$((20 + (start + i) % 200))
    exec {domain_lock_fd}>>"/tmp/hapsim-test-domain-$d.lock" || continue
    if flock -n "$domain_lock_fd"; then domain=$d; return; fi
    exec {domain_lock_fd}>&-
  done
  domain=$((20 + start))  # all taken: share one, as before
}
claim_domain
pids=()
server_prefix=()  # e.g. (taskset -c 0): what start_server runs the server under
cleanup() { for p in "${pids[@]}"; do kill -KILL "$p" 2>/dev/null || true; done; }
trap cleanup EXIT

# The deadband coding (on by default) sends a pose or a model only when the
# force would feel different, plus keep-alives. Tests of the runtime's
# per-tick delivery and timing (model ages, counts, routing under load)
# ask for every pose and every model with these; tests/loop measures the
# deadband itself, and the end-to-end and safety tests run the defaults.
every_tick_server=(--model-deadband 0)
every_tick_client=(--pose-deadband-mm 0)

# Ends a test whose checks are in bash (checks.py's finish() for Python):
# 0 without failures; with failures, 75 when a bridge's or hapsim-load's own
# servo report shows the host stalled it for more than 10 ms (checks.py's
# rule) — retry_on_host_stall.sh then runs the test once more — else 1.
finish_checks() {
  [ "$1" -eq 0 ] && exit 0
  /usr/bin/python3 "$here/checks.py" stalled "$work"
  exit $?
}

start_server() {
  local sessions=$1; shift
  rm -f port
  "${server_prefix[@]}" "$bin/hapsim-server" --listen 127.0.0.1:0 --port-file port --sessions "$sessions" \
      --dds-domain "$domain" "$@" \
      >server.out 2>server.log &
  server=$!; pids+=("$server")
  for _ in $(seq 1 150); do [ -s port ] && break; sleep 0.1; done
  [ -s port ] || { echo "server did not start"; cat server.log; exit 1; }
  addr=127.0.0.1:$(cat port)
}

# stop_process VAR PID: SIGTERM the process, wait for it, store its exit code in VAR.
stop_process() {
  kill -TERM "$2" 2>/dev/null || true
  local rc=0
  wait "$2" || rc=$?
  printf -v "$1" '%s' "$rc"
}
