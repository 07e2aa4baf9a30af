#include "hapsim/streaming/viewer_link.h"

#include <algorithm>
#include <chrono>
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
  if (write_in_flight_ || WindowFull(now_ns)) {
    const bool superseded = held_snapshot_id_ != 0 && held_snapshot_id_ != snapshot->id;
    held_snapshot_id_ = snapshot->id;
    if (!superseded) return OfferResult::kBusy;
    ++coalesced_;
    return OfferResult::kCoalesced;
  }
  held_snapshot_id_ = 0;
  if (now_ns - last_send_ns_ < min_interval_ns_) return OfferResult::kRateLimited;
  sent_ns_[encoder_.next_seq % kMaxFramesInFlight] = now_ns;
  EncodeFrame(*snapshot, history, &encoder_, &frame_);
  frame_.set_sent_unix_s(std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count());
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

namespace {
constexpr std::int64_t kRttWindowNs = 10'000'000'000;
// A frame younger than the round trip plus this margin may still be on its
// way: the viewer's scheduling and the server's own write path.
constexpr std::int64_t kInFlightMarginNs = 2'000'000;
}  // namespace

bool ViewerLink::WindowFull(std::int64_t now_ns) const {
  if (ack_window_ == 0) return false;
  const std::uint64_t unacked = encoder_.next_seq - acked_frames_;
  if (unacked >= kMaxFramesInFlight) return true;
  const std::int64_t rtt_ns = LinkRoundTripNs();
  if (rtt_ns < 0) return unacked >= ack_window_;  // nothing measured: count every frame
  const std::int64_t on_wire_ns = rtt_ns + rtt_ns / 4 + kInFlightMarginNs;
  std::uint64_t overdue = 0;  // seqs are sent in order: the oldest come first
  for (std::uint64_t seq = acked_frames_; seq < encoder_.next_seq; ++seq) {
    if (now_ns - sent_ns_[seq % kMaxFramesInFlight] <= on_wire_ns) break;
    ++overdue;
  }
  return overdue >= ack_window_;
}

std::int64_t ViewerLink::LinkRoundTripNs() const {
  if (rtt_min_ns_ < 0) return rtt_previous_min_ns_;
  if (rtt_previous_min_ns_ < 0) return rtt_min_ns_;
  return std::min(rtt_min_ns_, rtt_previous_min_ns_);
}

void ViewerLink::OnAck(std::uint64_t applied_seq, std::uint64_t held_us, std::int64_t now_ns) {
  std::lock_guard lock(mutex_);
  // Acks only move forward and never past what was sent.
  if (applied_seq >= encoder_.next_seq || applied_seq < acked_frames_) return;
  acked_frames_ = applied_seq + 1;
  if (encoder_.next_seq - applied_seq > kMaxFramesInFlight) return;  // its send time was overwritten
  const std::int64_t held_ns = static_cast<std::int64_t>(std::min<std::uint64_t>(held_us, 60'000'000)) * 1000;
  const std::int64_t rtt_ns = std::max<std::int64_t>(0, now_ns - sent_ns_[applied_seq % kMaxFramesInFlight] - held_ns);
  if (now_ns - rtt_window_start_ns_ > kRttWindowNs) {
    rtt_previous_min_ns_ = rtt_min_ns_;
    rtt_min_ns_ = -1;
    rtt_window_start_ns_ = now_ns;
  }
  if (rtt_min_ns_ < 0 || rtt_ns < rtt_min_ns_) rtt_min_ns_ = rtt_ns;
}

double ViewerLink::link_round_trip_s() const {
  std::lock_guard lock(mutex_);
  const std::int64_t ns = LinkRoundTripNs();
  return ns < 0 ? -1.0 : static_cast<double>(ns) * 1e-9;
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
