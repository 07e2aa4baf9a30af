// One direction of an emulated link: decides, for each packet offered at a
// time, whether it is dropped and, if not, when it leaves the link. Pure
// logic on a caller-given clock and a seeded generator, so its statistics
// are tested exactly; the forwarder owns the clock and the packets.
#pragma once
#include <cstdint>
#include <random>

#include "hapsim/netlab/link_profile.h"

namespace hapsim::netlab {

enum class Fate : std::uint8_t {
  kDelivered,
  kLost,    // random loss
  kBurst,   // dropped inside a loss burst
  kQueue,   // the bandwidth cap's queue was full
  kOutage,  // inside a scheduled outage
};

const char* ToString(Fate fate);

struct Admission {
  Fate fate = Fate::kDelivered;
  std::int64_t leave_ns = 0;  // when the packet leaves this link (kDelivered only)
};

class LinkModel {
 public:
  // start_ns: the clock's value at the emulation's start (outages count from it).
  LinkModel(const LinkProfile& profile, std::uint64_t seed, std::int64_t start_ns);

  // A packet of `bytes` bytes enters the link at now_ns. Calls must come in
  // non-decreasing now_ns.
  Admission Offer(std::int64_t now_ns, std::size_t bytes);

  bool in_burst() const { return in_burst_; }

 private:
  bool InOutage(std::int64_t now_ns) const;

  LinkProfile profile_;
  std::mt19937_64 random_;
  std::uniform_real_distribution<double> unit_{0.0, 1.0};
  std::int64_t start_ns_;
  bool in_burst_ = false;
  std::int64_t wire_free_ns_ = 0;   // the cap's serializer is busy until then
  std::int64_t last_leave_ns_ = 0;  // FIFO: no packet leaves before the previous one
};

}  // namespace hapsim::netlab
