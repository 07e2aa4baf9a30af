// Any field values in a pose sample from a device: the server's pose filter
// either refuses it with a reason or returns a tool input that is finite,
// within 2 m of the origin, no faster than 10 m/s, with a unit orientation;
// the session id read from the sample never runs past its 64 bytes.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "hapsim/device_link/pose_filter.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  hapsim_dds_StylusPose pose;
  std::memset(&pose, 0, sizeof pose);
  // Fill the sample field by field from the input (raw doubles: NaN, inf,
  // subnormals and huge values all reachable).
  std::size_t at = 0;
  auto take = [&](void* field, std::size_t n) {
    const std::size_t k = std::min(n, size - at);
    std::memcpy(field, data + at, k);
    at += k;
  };
  take(pose.session, sizeof pose.session);
  take(pose.pos_m, sizeof pose.pos_m);
  take(pose.quat_wxyz, sizeof pose.quat_wxyz);
  take(pose.vel_m_per_s, sizeof pose.vel_m_per_s);
  take(&pose.seq, sizeof pose.seq);
  const std::string_view session = hapsim::service::SessionIdOf(pose.session);
  if (session.size() >= sizeof pose.session || (!session.empty() && session.data() != pose.session)) std::abort();

  const hapsim::service::PoseLimits limits;
  hapsim::service::PoseRejection why = hapsim::service::PoseRejection::kNone;
  const auto tool = hapsim::service::FilterPose(pose, limits, &why);
  if (!tool) {
    if (why == hapsim::service::PoseRejection::kNone) std::abort();  // a refusal always says why
    return 0;
  }
  if (!tool->valid || !tool->tip_W_m.allFinite() || !tool->velocity_W_m_per_s.allFinite()) std::abort();
  if (tool->tip_W_m.norm() > limits.max_distance_m) std::abort();
  if (tool->velocity_W_m_per_s.norm() > limits.max_speed_m_per_s * (1.0 + 1e-12)) std::abort();
  if (std::abs(tool->orientation_W.norm() - 1.0) > 1e-9) std::abort();
  return 0;
}
