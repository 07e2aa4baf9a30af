// What one emulated access link does to the packets crossing it, in one
// direction: a fixed one-way delay, a jitter, random and bursty loss, a
// bandwidth cap with a bounded queue, and scheduled outages. A host's
// profile applies to both directions of its link to the emulated switch,
// so a packet from host A to host B crosses A's link, then B's.
#pragma once
#include <string>
#include <vector>

namespace hapsim::netlab {

// A window of time in which the link drops everything [s since start].
struct Outage {
  double start_s = 0.0;
  double duration_s = 0.0;
};

struct LinkProfile {
  double delay_ms = 0.0;   // one-way propagation delay
  double jitter_ms = 0.0;  // each packet's delay is uniform in delay ± jitter (never below 0)
  bool reorder = false;    // false: a later packet never overtakes an earlier one (a single path)
  double loss = 0.0;       // probability that a packet is dropped, outside bursts [0, 1]
  // Bursty loss (Gilbert-Elliott): each packet may start a burst with
  // probability burst_rate; in a burst every packet is dropped, and the
  // burst ends after each packet with probability 1 / burst_packets (a mean
  // of burst_packets packets, geometric).
  double burst_rate = 0.0;
  double burst_packets = 0.0;
  double rate_mbit_s = 0.0;  // bandwidth cap (0: none)
  double queue_ms = 50.0;    // with a cap: a packet that would wait longer than this is dropped
  std::vector<Outage> outages;
};

// Parses "delay_ms=10,jitter_ms=5,loss=0.01,burst_rate=0.001,burst_packets=150,
// rate_mbit_s=100,queue_ms=50,reorder=1,outage=3+2" (every key optional; outage
// START_S+DURATION_S may repeat). Empty text is a perfect link. False with
// *error naming the key or value on bad input.
bool ParseLinkProfile(const std::string& text, LinkProfile* profile, std::string* error);

// The profile as the text ParseLinkProfile reads (for reports).
std::string ToString(const LinkProfile& profile);

}  // namespace hapsim::netlab
