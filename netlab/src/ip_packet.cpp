#include "hapsim/netlab/ip_packet.h"

#include <arpa/inet.h>

namespace hapsim::netlab {

PacketRoute RouteOf(const std::uint8_t* packet, std::size_t bytes) {
  PacketRoute route;
  // IPv4: version 4 in the high nibble, a header of at least 20 bytes.
  if (bytes < 20 || (packet[0] >> 4) != 4) return route;
  const std::size_t header_bytes = static_cast<std::size_t>(packet[0] & 0x0f) * 4;
  if (header_bytes < 20 || header_bytes > bytes) return route;
  route.ipv4 = true;
  route.destination = (std::uint32_t{packet[16]} << 24) | (std::uint32_t{packet[17]} << 16) |
                      (std::uint32_t{packet[18]} << 8) | std::uint32_t{packet[19]};
  const bool multicast = (route.destination >> 28) == 0xe;  // 224.0.0.0/4
  route.to_all = multicast || route.destination == 0xffffffffu;
  return route;
}

bool ParseIpv4(const char* text, std::uint32_t* address) {
  in_addr a{};
  if (inet_pton(AF_INET, text, &a) != 1) return false;
  *address = ntohl(a.s_addr);
  return true;
}

}  // namespace hapsim::netlab
