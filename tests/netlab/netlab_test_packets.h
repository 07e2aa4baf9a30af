// Hosts and IPv4 packets for the netlab tests (only the fields the switch
// reads: version, header length, destination).
#pragma once
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "hapsim/netlab/ip_packet.h"
#include "hapsim/netlab/link_switch.h"

namespace hapsim::netlab::test {

inline constexpr std::int64_t kNsPerMs = 1'000'000;

inline std::vector<std::uint8_t> Ipv4To(const char* destination, std::size_t bytes = 60) {
  std::vector<std::uint8_t> p(bytes, 0);
  p[0] = 0x45;  // version 4, 20-byte header
  std::uint32_t a = 0;
  EXPECT_TRUE(ParseIpv4(destination, &a));
  p[16] = a >> 24, p[17] = (a >> 16) & 0xff, p[18] = (a >> 8) & 0xff, p[19] = a & 0xff;
  return p;
}

inline HostSpec Host(const char* name, const char* address, const std::string& link) {
  HostSpec h;
  h.name = name;
  EXPECT_TRUE(ParseIpv4(address, &h.address));
  std::string error;
  EXPECT_TRUE(ParseLinkProfile(link, &h.link, &error)) << error;
  return h;
}

}  // namespace hapsim::netlab::test
