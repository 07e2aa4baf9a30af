// One open Subscribe stream as the frame pump sees it. The pump offers each
// new snapshot; the link sends it only when no write is in flight and the
// viewer's rate allows — otherwise the snapshot is skipped and a later one
// (newest state wins) goes out instead. With an ack window, "no write in
// flight" also means "fewer than ack_window frames the viewer has not
// acknowledged", so the backlog is bounded end to end, not only up to the
// HTTP/2 buffers. A slow viewer never slows the physics and never lags far.
// Frames still on the wire are not backlog: the link measures the network's
// round trip from the acks (each ack's time since its frame went out, less
// the time the viewer says it held the frame; the lowest over the last 10 s)
// and counts against the window only frames unacknowledged for longer than
// that. A far viewer then gets the full frame rate (the window grows by the
// bandwidth-delay product) while a slow viewer near or far still lags at
// most ack_window of its own frames.
#pragma once
#include <grpcpp/grpcpp.h>

#include <array>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>

#include "hapsim/runtime/scene_snapshot.h"
#include "hapsim/streaming/frame_encoder.h"
#include "hapsim/v1/viewer.pb.h"

namespace hapsim::service {

class ViewerLink {
 public:
  // What the link drives: the gRPC reactor of the stream.
  struct Stream {
    virtual ~Stream() = default;
    virtual void StartFrameWrite(const hapsim::v1::Frame* frame) = 0;
    virtual void FinishStream(const grpc::Status& status) = 0;
  };

  // ack_window: frames that may be unacknowledged beyond the link's round
  // trip (0: no limit). At most kMaxFramesInFlight are unacknowledged at once.
  static constexpr std::uint32_t kMaxFramesInFlight = 128;
  ViewerLink(std::string name, double max_rate_hz, double quantum_m, std::uint32_t ack_window);

  enum class OfferResult {
    kSent,
    kNotNeeded,    // no stream yet, finished, or this snapshot was already sent
    kRateLimited,  // the viewer asked for fewer frames (max_rate_hz): by design
    kBusy,         // previous write or the ack window outstanding: held, may still go out
    kCoalesced,    // busy, and a newer snapshot replaced one this viewer never got (slow viewer)
  };
  // Frame pump: send this snapshot if the stream is free and due (topology
  // edits from the session's history, which has absorbed the snapshot).
  OfferResult Offer(const std::shared_ptr<const SceneSnapshot>& snapshot, const TopologyHistory& history,
             std::int64_t now_ns);
  // Session closed or server stopping: end the stream with this status.
  void Close(const grpc::Status& status);

  // Reactor callbacks.
  void Attach(Stream* stream);
  void OnWriteDone(bool ok);
  void OnCancelled();
  // held_us: what the viewer says it spent on the frame before acking.
  void OnAck(std::uint64_t applied_seq, std::uint64_t held_us, std::int64_t now_ns);
  void Detach();  // OnDone: the stream object is about to be destroyed

  const std::string& name() const { return name_; }
  std::uint64_t frames_sent() const;
  std::uint64_t bytes_sent() const;
  std::uint64_t snapshots_coalesced() const;  // kCoalesced offers: snapshots this viewer never got
  std::uint64_t last_frame_bytes() const;     // size of the frame the last kSent offer wrote
  double link_round_trip_s() const;           // the network's round trip as measured; -1: no ack yet

 private:
  // recursive: gRPC may run a reaction inline from StartWrite/Finish.
  mutable std::recursive_mutex mutex_;
  Stream* stream_ = nullptr;
  bool write_in_flight_ = false;
  bool finished_ = false;
  std::string name_;
  std::int64_t min_interval_ns_ = 0;
  std::uint32_t ack_window_ = 0;
  std::uint64_t acked_frames_ = 0;  // frames acknowledged: seqs [0, acked_frames_)
  std::array<std::int64_t, kMaxFramesInFlight> sent_ns_{};  // send time of seq s at s % kMaxFramesInFlight
  // Lowest link round trip over the current and the previous 10 s window
  // (a windowed minimum: a route that got longer is seen within 20 s).
  std::int64_t rtt_min_ns_ = -1, rtt_previous_min_ns_ = -1, rtt_window_start_ns_ = 0;
  std::int64_t last_send_ns_ = 0;
  std::uint64_t last_snapshot_id_ = 0;
  std::uint64_t held_snapshot_id_ = 0;  // newest snapshot refused as busy (0: none)
  bool WindowFull(std::int64_t now_ns) const;  // frames unacknowledged past the round trip >= ack_window
  std::int64_t LinkRoundTripNs() const;        // -1: not measured yet

  StreamEncoderState encoder_;
  hapsim::v1::Frame frame_;  // the frame in flight (must outlive the write)
  std::uint64_t frames_sent_ = 0, bytes_sent_ = 0, coalesced_ = 0, last_frame_bytes_ = 0;
};

}  // namespace hapsim::service
