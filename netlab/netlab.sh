#!/usr/bin/env bash
# hapsim's network lab: emulated hosts (Linux network namespaces) joined by
# hapsim-linkem, a user-space link emulator, so a server, trainee PCs and a
# viewer run on one machine as if on a LAN or WAN with delay, jitter, loss
# and outages. Needs root (or CAP_NET_ADMIN), iproute2 and /dev/net/tun.
#
#   netlab.sh up LAB [--seconds S] [--owner PID] [--realtime] [--seed N] HOST[=LINK] ...
#       Host i (from 1, in the order given) is namespace hapsim-LAB-HOST with
#       TUN device hl0 at 10.77.0.i/24; LINK is its access link, as
#       hapsim-linkem's --host keys (delay_ms=10,jitter_ms=5,loss=0.01,...).
#       The lab lives --seconds (default 600) at most, and is removed by the
#       next `up` or `sweep` once --owner (default: the caller) has exited.
#       --realtime runs the emulator at SCHED_FIFO priority 10 and has it poll
#       without sleeping for the last 300 us (HAPSIM_LINKEM_SPIN_LEAD_US)
#       before each packet is due: an idle CPU can wake 0.1 ms or more late.
#   netlab.sh exec LAB HOST COMMAND...   run a command on a host
#   netlab.sh addr LAB HOST              print a host's address
#   netlab.sh report LAB                 the emulator's JSON report (after down)
#   netlab.sh down LAB                   stop the emulator, remove the namespaces
#   netlab.sh sweep                      remove every lab whose owner is gone
#   netlab.sh check                      exit 0 if this machine can run a lab, else 77 and why
#
# Nothing is touched outside the namespaces it makes: traffic stays on their
# hl0 devices, and `down` (or the lab's time limit, or `sweep`) removes them.
# HAPSIM_LINKEM names the emulator (default: the build tree's bin/hapsim-linkem).
set -euo pipefail

state_root=${HAPSIM_NETLAB_STATE:-/run/hapsim-netlab}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
linkem=${HAPSIM_LINKEM:-$here/../build/bin/hapsim-linkem}

die() { echo "netlab: $*" >&2; exit 1; }
netns_of() { echo "hapsim-$1-$2"; }
lab_dir() { echo "$state_root/$1"; }

valid_name() {  # namespace names and hl0 stay short and shell-safe
  [[ $1 =~ ^[a-z0-9]{1,12}$ ]] || die "'$1' must be 1-12 lowercase letters or digits"
}

check() {
  local why=""
  if [ "$(id -u)" != 0 ] && ! capsh --has-p=cap_net_admin 2>/dev/null; then why="needs root (CAP_NET_ADMIN)"
  elif ! command -v ip >/dev/null; then why="needs iproute2's ip"
  elif [ ! -c /dev/net/tun ]; then why="needs /dev/net/tun"
  elif ! ip netns add "hapsim-probe-$$" 2>/dev/null; then why="cannot make network namespaces here"
  else
    ip netns del "hapsim-probe-$$"
  fi
  if [ -n "$why" ]; then echo "netlab: $why"; return 77; fi
}

down() {
  local lab=$1 dir
  dir=$(lab_dir "$lab")
  if [ -f "$dir/linkem.pid" ]; then
    local pid
    pid=$(cat "$dir/linkem.pid")
    kill -TERM "$pid" 2>/dev/null || true
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -KILL "$pid" 2>/dev/null || true
    rm -f "$dir/linkem.pid"
  fi
  if [ -f "$dir/hosts" ]; then
    while read -r host _; do
      local ns
      ns=$(netns_of "$lab" "$host")
      # Processes still on the host would keep its namespace alive.
      for pid in $(ip netns pids "$ns" 2>/dev/null); do kill -KILL "$pid" 2>/dev/null || true; done
      ip netns del "$ns" 2>/dev/null || true
    done <"$dir/hosts"
    rm -f "$dir/hosts"
  fi
}

sweep() {
  [ -d "$state_root" ] || return 0
  for dir in "$state_root"/*/; do
    [ -d "$dir" ] || continue
    local lab owner
    lab=$(basename "$dir")
    if [ ! -f "$dir/hosts" ]; then rm -rf "$dir"; continue; fi  # taken down already: only its report is left
    owner=$(cat "$dir/owner" 2>/dev/null || echo 0)
    if [ "$owner" = 0 ] || ! kill -0 "$owner" 2>/dev/null; then
      echo "netlab: removing lab $lab (its owner $owner is gone)" >&2
      down "$lab"
      rm -rf "$dir"
    fi
  done
}

up() {
  local lab=$1 seconds=600 owner=$PPID realtime="" seed=1
  shift
  valid_name "$lab"
  while [ $# -gt 0 ]; do
    case $1 in
      --seconds) seconds=$2; shift 2 ;;
      --owner) owner=$2; shift 2 ;;
      --realtime) realtime="--realtime --spin-lead-us ${HAPSIM_LINKEM_SPIN_LEAD_US:-300}"; shift ;;
      --seed) seed=$2; shift 2 ;;
      -*) die "unknown option $1" ;;
      *) break ;;
    esac
  done
  [ $# -ge 2 ] || die "a lab needs at least two hosts"
  [ -x "$linkem" ] || die "no link emulator at $linkem (build hapsim-linkem, or set HAPSIM_LINKEM)"
  sweep
  local dir
  dir=$(lab_dir "$lab")
  [ ! -f "$dir/hosts" ] || die "lab $lab is up already (netlab.sh down $lab)"
  mkdir -p "$dir"
  echo "$owner" >"$dir/owner"
  rm -f "$dir/report.json" "$dir/ready"
  local i=0 args=()
  : >"$dir/hosts"
  for spec in "$@"; do
    i=$((i + 1))
    local host=${spec%%=*} link="" ns address
    [ "$spec" != "$host" ] && link=${spec#*=}
    valid_name "$host"
    ns=$(netns_of "$lab" "$host")
    address=10.77.0.$i
    echo "$host $address" >>"$dir/hosts"
    ip netns add "$ns"
    ip -n "$ns" link set lo up
    ip -n "$ns" tuntap add dev hl0 mode tun
    ip -n "$ns" addr add "$address/24" dev hl0
    ip -n "$ns" link set hl0 up
    ip -n "$ns" route add 224.0.0.0/4 dev hl0  # DDS discovery's multicast, if the config uses it
    ip netns exec "$ns" sysctl -qw net.ipv6.conf.hl0.disable_ipv6=1
    args+=(--host "$ns,$address${link:+,$link}")
  done
  "$linkem" "${args[@]}" --seconds "$seconds" --seed "$seed" $realtime \
      --report "$dir/report.json" --ready-file "$dir/ready" >"$dir/linkem.log" 2>&1 &
  echo $! >"$dir/linkem.pid"
  for _ in $(seq 100); do
    [ -f "$dir/ready" ] && return 0
    kill -0 "$(cat "$dir/linkem.pid")" 2>/dev/null || break
    sleep 0.05
  done
  cat "$dir/linkem.log" >&2
  down "$lab"
  die "the link emulator did not start"
}

host_exec() {
  local lab=$1 host=$2
  shift 2
  grep -q "^$host " "$(lab_dir "$lab")/hosts" 2>/dev/null || die "lab $lab has no host $host"
  exec ip netns exec "$(netns_of "$lab" "$host")" "$@"
}

addr() {
  local line
  line=$(grep "^$2 " "$(lab_dir "$1")/hosts" 2>/dev/null) || die "lab $1 has no host $2"
  echo "${line#* }"
}

command=${1:-}
[ -n "$command" ] || die "usage: netlab.sh up|exec|addr|report|down|sweep|check ... (see the head of this file)"
shift
case $command in
  up) up "$@" ;;
  exec) host_exec "$@" ;;
  addr) addr "$@" ;;
  report) cat "$(lab_dir "$1")/report.json" ;;
  down) down "$1"; rm -f "$(lab_dir "$1")/owner" "$(lab_dir "$1")/ready" ;;
  sweep) sweep ;;
  check) check ;;
  *) die "unknown command $command" ;;
esac
