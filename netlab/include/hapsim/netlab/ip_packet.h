// The little the forwarder reads of an IP packet from a TUN device: its
// version and IPv4 destination, to route it to a host (or to all of them).
#pragma once
#include <cstddef>
#include <cstdint>

namespace hapsim::netlab {

struct PacketRoute {
  bool ipv4 = false;              // false: not a well-formed IPv4 packet (not forwarded)
  std::uint32_t destination = 0;  // host byte order
  bool to_all = false;            // multicast or broadcast: every host but the sender
};

// Reads the header of `bytes` bytes at `packet` (as a TUN device without
// packet info hands them over). Never reads past `bytes`.
PacketRoute RouteOf(const std::uint8_t* packet, std::size_t bytes);

// "10.77.0.2" -> host-order address; false on anything else.
bool ParseIpv4(const char* text, std::uint32_t* address);

}  // namespace hapsim::netlab
