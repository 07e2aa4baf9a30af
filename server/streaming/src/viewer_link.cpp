#include "hapsim/streaming/viewer_link.h"

#include <algorithm>
#include <cmath>

namespace hapsim::service {

ViewerLink::ViewerLink(std::string name, double max_rate_hz, double quantum_m, std::uint32_t ack_window)
    : name_(std::move(name)), ack_window_(ack_window) {
  encoder_.quantum_m = quantum_m;
  if (max_rate_hz > 0.0) min_interval_ns_ = static_cast<std::int64_t>(std::llround(1e9 / max_rate_hz));
}

void ViewerLink::Attach(Stream* stream) {
  std::lock_guard lock(mutex_);
  stream_ = stream;
}

ViewerLink::OfferResult ViewerLink::Offer(const std::shared_ptr<const SceneSnapshot>& snapshot, const TopologyHistory& history,
                       std::int64_t now_ns) {
  std::lock_guard lock(mutex_);
  if (!stream_ || finished_ || !snapshot || snapshot->id == last_snapshot_id_) return OfferResult::kNotNeeded;
  const bool window_full = ack_window_ > 0 && encoder_.next_seq - acked_frames_ >= ack_window_;
  if (write_in_flight_ || window_full) {
    const bool superseded = held_snapshot_id_ != 0 && held_snapshot_id_ != snapshot->id;
    held_snapshot_id_ = snapshot->id;
    if (!superseded) return OfferResult::kBusy;
    ++coalesced_;
    return OfferResult::kCoalesced;
  }
  held_snapshot_id_ = 0;
  if (now_ns - last_send_ns_ < min_interval_ns_) return OfferResult::kRateLimited;
  EncodeFrame(*snapshot, history, &encoder_, &frame_);
  last_snapshot_id_ = snapshot->id;
  last_send_ns_ = now_ns;
  write_in_flight_ = true;
  ++frames_sent_;
  last_frame_bytes_ = frame_.ByteSizeLong();
  bytes_sent_ += last_frame_bytes_;
  stream_->StartFrameWrite(&frame_);
  return OfferResult::kSent;
}

void ViewerLink::OnWriteDone(bool ok) {
  std::lock_guard lock(mutex_);
  write_in_flight_ = false;
  if (!ok && !finished_ && stream_) {
    finished_ = true;  // the client is gone; the stream ends
    stream_->FinishStream(grpc::Status(grpc::StatusCode::UNAVAILABLE, "write failed"));
  }
}

void ViewerLink::OnAck(std::uint64_t applied_seq) {
  std::lock_guard lock(mutex_);
  // Acks only move forward and never past what was sent.
  if (applied_seq < encoder_.next_seq) acked_frames_ = std::max(acked_frames_, applied_seq + 1);
}

void ViewerLink::OnCancelled() {
  std::lock_guard lock(mutex_);
  if (finished_ || !stream_) return;
  finished_ = true;
  stream_->FinishStream(grpc::Status::CANCELLED);
}

void ViewerLink::Close(const grpc::Status& status) {
  std::lock_guard lock(mutex_);
  if (finished_ || !stream_) return;
  finished_ = true;
  stream_->FinishStream(status);
}

void ViewerLink::Detach() {
  std::lock_guard lock(mutex_);
  stream_ = nullptr;
  finished_ = true;
}

std::uint64_t ViewerLink::frames_sent() const {
  std::lock_guard lock(mutex_);
  return frames_sent_;
}
std::uint64_t ViewerLink::bytes_sent() const {
  std::lock_guard lock(mutex_);
  return bytes_sent_;
}
std::uint64_t ViewerLink::last_frame_bytes() const {
  std::lock_guard lock(mutex_);
  return last_frame_bytes_;
}

std::uint64_t ViewerLink::snapshots_coalesced() const {
  std::lock_guard lock(mutex_);
  return coalesced_;
}

}  // namespace hapsim::service
