// Which device drives a session, and which of its poses are new. The first
// device to stream a pose owns the session until it has been silent for the
// pose timeout; meanwhile poses from any other device id are refused (and
// counted by the caller), so a second stylus pointed at the same session
// cannot fight the trainee's. From the owner, only a pose whose seq is above
// the last accepted one is new: a duplicate, a late (reordered) sample, or a
// second bridge started with the same --device-id (its seq starts again near
// 0) is refused as stale. A bridge restarted under the same device id is
// accepted once the old stream has been silent for the timeout, like any new
// device. Used by the DDS thread only (not thread-safe).
#pragma once
#include <cstdint>

namespace hapsim::service {

enum class PoseVerdict {
  kAccepted,
  kOtherDevice,  // another device owns the session
  kStale,        // from the owner, but seq not above the last accepted one
};

class DeviceOwnership {
 public:
  explicit DeviceOwnership(std::int64_t timeout_ns) : timeout_ns_(timeout_ns) {}

  // A pose (device_id, seq) arrived at now_ns.
  PoseVerdict Accept(std::uint32_t device_id, std::uint64_t seq, std::int64_t now_ns) {
    const bool owner_streaming = has_owner_ && now_ns - last_pose_ns_ <= timeout_ns_;
    if (owner_streaming && device_id != owner_) return PoseVerdict::kOtherDevice;
    if (owner_streaming && seq <= last_seq_) return PoseVerdict::kStale;
    has_owner_ = true;
    owner_ = device_id;
    last_seq_ = seq;
    last_pose_ns_ = now_ns;
    return PoseVerdict::kAccepted;
  }
  bool has_owner() const { return has_owner_; }
  std::uint32_t owner() const { return owner_; }

 private:
  std::int64_t timeout_ns_;
  bool has_owner_ = false;
  std::uint32_t owner_ = 0;
  std::uint64_t last_seq_ = 0;
  std::int64_t last_pose_ns_ = 0;
};

}  // namespace hapsim::service
