// Any field values in a batch of DDS pose samples, routed into a session the
// way ServerDds does it (RoutePoseBatch: pose filter, session id against the
// partition's, device ownership, seq order). The first byte advances a fake
// clock by 0-255 ms (so ownership timeouts are reached), the rest is cut
// into up to 16 raw StylusPose samples. Invariants: every sample is counted
// exactly once (rejected, wrong session, other device, stale or accepted),
// the session counts as received exactly the accepted ones, and a batch with
// an accepted pose says so (the caller would wake the session).
#include <spdlog/spdlog.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "fuzz_setup.h"
#include "hapsim/core/scenes/scene.h"
#include "hapsim/device_link/pose_router.h"

namespace {

using namespace hapsim;

class NullPort final : public service::SessionPort {
 public:
  bool WriteForceModel(const service::ForceModelMessage&) override { return true; }
};

service::Session& TheSession() {
  static service::Session* session = [] {
    service::SessionConfig config;
    config.id = "s1";
    core::SceneSpec spec;
    spec.params["grid_nodes"] = 5;
    return new service::Session(config, core::MakeScene(spec), std::make_shared<NullPort>());
  }();  // lives for the process (the fuzzer exits without unwinding)
  return *session;
}

std::uint64_t Total(const service::ServerDdsCounters& c) {
  return c.poses_rejected.load() + c.poses_wrong_session.load() + c.poses_other_device.load() + c.poses_stale.load() +
         c.poses_accepted.load();
}

// HAPSIM_FUZZ_WRITE_SEEDS=DIR: a good batch, and one per refusal kind.
void WriteSeeds(const std::string& dir) {
  auto pose = [](std::uint32_t device, const char* session, std::uint64_t seq, double x) {
    hapsim_dds_StylusPose p;
    std::memset(&p, 0, sizeof p);
    p.device_id = device;
    std::strncpy(p.session, session, sizeof p.session - 1);
    p.seq = seq;
    p.pos_m[0] = x;
    p.pos_m[2] = 0.01;
    p.quat_wxyz[0] = 1.0;
    return p;
  };
  auto write = [&](const std::string& name, std::uint8_t advance_ms, const std::vector<hapsim_dds_StylusPose>& poses) {
    std::string bytes(1, static_cast<char>(advance_ms));
    for (const auto& p : poses) bytes.append(reinterpret_cast<const char*>(&p), sizeof p);
    std::ofstream(dir + "/" + name, std::ios::binary) << bytes;
  };
  write("good", 1, {pose(7, "s1", 1, 0.0), pose(7, "s1", 2, 0.001)});
  write("stale_and_other", 1, {pose(7, "s1", 5, 0.0), pose(7, "s1", 5, 0.0), pose(8, "s1", 1, 0.0)});
  write("wrong_session", 1, {pose(7, "s2", 9, 0.0)});
  write("bad_values", 1, {pose(7, "s1", 10, 5.0)});
  write("owner_timeout", 255, {pose(9, "s1", 1, 0.0)});
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  hapsim::fuzz::SetUpServiceFuzzer(&WriteSeeds);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  static std::int64_t now_ns = 1'000'000'000;
  static service::ServerDdsCounters counters;
  static service::WarningLimiter warnings;
  now_ns += static_cast<std::int64_t>(data[0]) * 1'000'000;
  std::vector<hapsim_dds_StylusPose> batch;
  for (std::size_t at = 1; at < size && batch.size() < 16; at += sizeof(hapsim_dds_StylusPose)) {
    hapsim_dds_StylusPose p;
    std::memset(&p, 0, sizeof p);
    std::memcpy(&p, data + at, std::min(sizeof p, size - at));  // raw bytes: any field value, strings without NUL
    batch.push_back(p);
  }
  service::Session& session = TheSession();
  const std::uint64_t before = Total(counters), accepted_before = counters.poses_accepted.load();
  const std::uint64_t received_before = session.counters().poses.received.load();
  const bool offered = service::RoutePoseBatch(session, batch, service::PoseLimits{}, now_ns, &counters, &warnings);
  const std::uint64_t accepted = counters.poses_accepted.load() - accepted_before;
  if (Total(counters) - before != batch.size()) std::abort();                             // each counted once
  if (session.counters().poses.received.load() - received_before != accepted) std::abort();  // the session agrees
  if (offered != (accepted > 0)) std::abort();
  return 0;
}
