// Which device drives a session. The first device to stream a pose owns the
// session until it has been silent for the pose timeout; meanwhile poses from
// any other device id are refused (and counted by the caller), so a second
// stylus pointed at the same session cannot fight the trainee's. Used by the
// DDS thread only (not thread-safe).
#pragma once
#include <cstdint>

namespace hapsim::service {

class DeviceOwnership {
 public:
  explicit DeviceOwnership(std::int64_t timeout_ns) : timeout_ns_(timeout_ns) {}

  // A pose from device_id arrived at now_ns: true if that device owns (or now
  // takes) the session, false if another device still does.
  bool Accept(std::uint32_t device_id, std::int64_t now_ns) {
    if (has_owner_ && device_id != owner_ && now_ns - last_pose_ns_ <= timeout_ns_) return false;
    has_owner_ = true;
    owner_ = device_id;
    last_pose_ns_ = now_ns;
    return true;
  }
  bool has_owner() const { return has_owner_; }
  std::uint32_t owner() const { return owner_; }

 private:
  std::int64_t timeout_ns_;
  bool has_owner_ = false;
  std::uint32_t owner_ = 0;
  std::int64_t last_pose_ns_ = 0;
};

}  // namespace hapsim::service
