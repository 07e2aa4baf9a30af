#!/usr/bin/env bash
# Writes a Cyclone DDS configuration for hapsim on a LAN: the server on one
# machine, trainee PCs' bridges (and load generators) on others. Every host
# of a deployment uses the same options but its own --interface.
#
#   make-dds-config.sh --interface NAME|ADDRESS [--peer ADDRESS]... [--discovery multicast|unicast]
#                      [--max-participants N] [--receive-buffer-mib N] [--out FILE]
#
# --interface    the network interface DDS may use (name like eth0, or its address).
# --peer         with --discovery unicast: every host's address (the server and every trainee
#                PC; listing this host's own address too is harmless). Repeat.
# --discovery    multicast (default without --peer): participants find each other by SPDP
#                multicast; unicast (default with --peer): only the peers are asked, for
#                networks that drop multicast. Either way DATA is unicast: AllowMulticast is
#                never "true", because a session's models would then go by multicast to the
#                whole LAN as soon as a second reader subscribed to them.
# --max-participants  highest automatic participant index (one per process on a host; the
#                unicast discovery asks each peer's ports for indices 0..N). Default 20.
# --receive-buffer-mib  UDP receive buffer asked per socket (default 4; the kernel grants at
#                most net.core.rmem_max: raise that first on a server with many sessions).
# Prints to stdout, or writes --out. docs/deploy.md says what to open in a firewall.
set -euo pipefail

interface="" discovery="" max_participants=20 receive_mib=4 out="" peers=()
usage() { sed -n '2,22p' "$0" | sed 's/^# \{0,1\}//'; }
die() { echo "make-dds-config.sh: $*" >&2; exit 2; }
while [ $# -gt 0 ]; do
  case $1 in
    --interface) interface=${2:-}; shift 2 ;;
    --peer) peers+=("${2:-}"); shift 2 ;;
    --discovery) discovery=${2:-}; shift 2 ;;
    --max-participants) max_participants=${2:-}; shift 2 ;;
    --receive-buffer-mib) receive_mib=${2:-}; shift 2 ;;
    --out) out=${2:-}; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    *) die "unknown option '$1' (--help)" ;;
  esac
done
[ -n "$interface" ] || die "--interface is required (the interface name, e.g. eth0, or its address)"
[[ $interface =~ ^[A-Za-z0-9._:-]+$ ]] || die "--interface '$interface' is not an interface name or address"
[ -n "$discovery" ] || { [ ${#peers[@]} -gt 0 ] && discovery=unicast || discovery=multicast; }
case $discovery in
  multicast) allow_multicast=spdp ;;
  unicast) allow_multicast=false; [ ${#peers[@]} -gt 0 ] || die "--discovery unicast needs --peer for every host" ;;
  *) die "--discovery must be multicast or unicast, got '$discovery'" ;;
esac
for p in "${peers[@]}"; do
  [[ $p =~ ^[A-Za-z0-9.-]+$ ]] || die "--peer '$p' is not an address or host name"
done
[[ $max_participants =~ ^[0-9]+$ ]] && [ "$max_participants" -ge 1 ] && [ "$max_participants" -le 120 ] ||
  die "--max-participants must be within [1, 120], got '$max_participants'"
[[ $receive_mib =~ ^[0-9]+$ ]] && [ "$receive_mib" -ge 1 ] && [ "$receive_mib" -le 256 ] ||
  die "--receive-buffer-mib must be within [1, 256], got '$receive_mib'"

if [[ $interface =~ ^[0-9.]+$ ]]; then
  interface_xml="<NetworkInterface address=\"$interface\"/>"
else
  interface_xml="<NetworkInterface name=\"$interface\"/>"
fi
peers_xml=""
if [ "$discovery" = unicast ]; then
  peers_xml="      <Peers>"$'\n'
  for p in "${peers[@]}"; do peers_xml+="        <Peer address=\"$p\"/>"$'\n'; done
  peers_xml+="      </Peers>"$'\n'
fi
config=$(cat <<XML
<?xml version="1.0" encoding="UTF-8"?>
<!-- hapsim on a LAN, made by deploy/make-dds-config.sh: interface $interface, $discovery discovery${peers[*]:+ (peers ${peers[*]})}.
     Data is unicast (AllowMulticast $allow_multicast): see docs/deploy.md. -->
<CycloneDDS xmlns="https://cdds.io/config">
  <Domain Id="any">
    <General>
      <Interfaces>
        $interface_xml
      </Interfaces>
      <AllowMulticast>$allow_multicast</AllowMulticast>
    </General>
    <Internal>
      <SocketReceiveBufferSize min="default" max="${receive_mib}MiB"/>
    </Internal>
    <Discovery>
      <ParticipantIndex>auto</ParticipantIndex>
      <!-- Announce every second, not Cyclone's 30 s: a lost announcement on a lossy
           link otherwise left a bridge without its server (zero force) for 1-2.6 s
           (tests/bench/first_force.sh, 10 % loss: 4 of 30 starts over 1 s; with 1 s,
           worst 0.57 s). One small packet per peer per second. -->
      <SPDPInterval>1s</SPDPInterval>
      <MaxAutoParticipantIndex>$max_participants</MaxAutoParticipantIndex>
${peers_xml}    </Discovery>
  </Domain>
</CycloneDDS>
XML
)
if [ -n "$out" ]; then printf '%s\n' "$config" >"$out"; else printf '%s\n' "$config"; fi
