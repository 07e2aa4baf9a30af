// Attaching to a TUN device that lives in another network namespace.
#pragma once
#include <string>

namespace hapsim::netlab {

// Opens the existing TUN device `ifname` (made by `ip tuntap add mode tun`)
// in the network namespace `netns` (a name under /var/run/netns, as `ip netns
// add` makes them; "" is this process's own), non-blocking, packets without
// the packet-info header. The calling thread returns to its own namespace
// before this returns. -1 with *error saying what failed.
int OpenTunInNamespace(const std::string& netns, const std::string& ifname, std::string* error);

}  // namespace hapsim::netlab
