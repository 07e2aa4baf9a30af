#include "hapsim/viewer/viewer_client.h"

#include <chrono>
#include <cmath>
#include <cstdio>

#include <spdlog/spdlog.h>

namespace hapsim::viewer {

std::shared_ptr<grpc::Channel> MakeViewerChannel(const Connection& connection) {
  grpc::ChannelArguments args;
  args.SetInt(GRPC_ARG_HTTP2_BDP_PROBE, 0);
  args.SetInt(GRPC_ARG_HTTP2_STREAM_LOOKAHEAD_BYTES, 16 * 1024);
  args.SetMaxReceiveMessageSize(64 << 20);  // keyframes of large meshes
  return MakeChannel(connection, args);
}

std::shared_ptr<grpc::Channel> MakeViewerChannel(const std::string& address) {
  Connection connection;
  connection.address = address;
  return MakeViewerChannel(connection);
}

ViewerClient::ViewerClient(std::shared_ptr<grpc::Channel> channel, ViewerOptions options)
    : stub_(hapsim::v1::ViewerService::NewStub(channel)), channel_(std::move(channel)), options_(std::move(options)) {}

void ViewerClient::Stop() {
  stop_ = true;
  std::lock_guard lock(context_mutex_);
  if (active_context_) active_context_->TryCancel();
}

bool ViewerClient::Run() {
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  const auto deadline = options_.max_seconds > 0.0
                            ? start + std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(options_.max_seconds))
                            : clock::time_point::max();
  if (!channel_->WaitForConnected(std::chrono::system_clock::now() +
                                  std::chrono::milliseconds(static_cast<long>(options_.connect_timeout_s * 1e3)))) {
    stats_.final_status = "cannot connect to the server within " + std::to_string(options_.connect_timeout_s) + " s";
    return false;
  }
  bool first_stream = true;
  while (!stop_) {
    grpc::ClientContext context;
    AddToken(&context, options_.token);
    if (deadline != clock::time_point::max()) {
      context.set_deadline(std::chrono::system_clock::now() + (deadline - clock::now()));
    }
    {
      std::lock_guard lock(context_mutex_);
      active_context_ = &context;
    }
    if (stop_) context.TryCancel();
    auto stream = stub_->Subscribe(&context);
    hapsim::v1::ViewerMessage hello;
    auto* request = hello.mutable_subscribe();
    request->set_session_id(options_.session);
    request->set_max_rate_hz(options_.max_rate_hz);
    request->set_viewer_name(options_.name);
    request->set_ack_window(options_.ack_window);
    stream->Write(hello);  // a failure shows up as the stream's final status
    hapsim::v1::ViewerMessage ack;
    cache_.Invalidate();
    bool resubscribe = false, limit_reached = false;
    hapsim::v1::Frame frame;
    while (stream->Read(&frame)) {
      ++stats_.frames;
      stats_.bytes += frame.ByteSizeLong();
      if (frame.has_keyframe()) ++stats_.keyframes; else ++stats_.deltas;
      if (frame.has_topology()) ++stats_.topology_frames;
      for (const auto& e : frame.events()) {
        ++stats_.events[e.kind()];
        if (e.kind() == "cut_end") stats_.incisions_mm.push_back(1e3 * e.value());
        if (e.kind() == "puncture") {
          // Layer names come with the keyframe, which precedes any event.
          const auto& names = frame.has_keyframe() ? std::vector<std::string>(frame.keyframe().layer_names().begin(),
                                                                              frame.keyframe().layer_names().end())
                                                   : cache_.layer_names();
          const bool known = e.layer() >= 0 && static_cast<std::size_t>(e.layer()) < names.size();
          char depth[32];
          // The event's own position: the tip at the puncture instant, below
          // the top surface at z = 0.
          const double z_m = e.where_m_size() == 3 ? e.where_m(2) : 0.0;
          std::snprintf(depth, sizeof depth, "@%.2fmm", -z_m * 1e3);
          stats_.punctures.push_back((known ? names[static_cast<std::size_t>(e.layer())] : "layer" + std::to_string(e.layer())) + depth);
        }
      }
      stats_.last_sim_time_s = frame.sim_time_s();
      // The 1 kHz peak since the previous frame; a server that does not send it: the frame's own force.
      double peak_N = frame.peak_force_n();
      if (peak_N == 0.0 && frame.tool().force_n_size() == 3) {
        peak_N = std::sqrt(frame.tool().force_n(0) * frame.tool().force_n(0) +
                           frame.tool().force_n(1) * frame.tool().force_n(1) +
                           frame.tool().force_n(2) * frame.tool().force_n(2));
      }
      stats_.peak_tool_force_N = std::max(stats_.peak_tool_force_N, peak_N);
      stats_.last_contact_state = frame.tool().contact_state();

      const bool injected_loss = first_stream && options_.debug_drop_seq >= 0 &&
                                 frame.seq() == static_cast<std::uint64_t>(options_.debug_drop_seq);
      if (!injected_loss) {
        std::string why;
        const ApplyResult result = cache_.Apply(frame, &why);
        if (result != ApplyResult::kApplied) {
          if (result == ApplyResult::kGap) ++stats_.gaps;
          if (result == ApplyResult::kTopologyMismatch) ++stats_.topology_mismatches;
          if (result == ApplyResult::kMalformed) ++stats_.malformed;
          spdlog::warn("frame {} refused ({}): {}; resubscribing for a keyframe", frame.seq(), ToString(result), why);
          resubscribe = true;
          break;
        }
        if (options_.on_frame) options_.on_frame(frame, cache_);
      }
      // Acknowledge what is applied (or deliberately dropped): the server sends
      // at most ack_window frames ahead of this.
      ack.mutable_ack()->set_applied_seq(frame.seq());
      stream->Write(ack);
      if (options_.max_frames > 0 && stats_.frames >= options_.max_frames) {
        limit_reached = true;
        break;
      }
    }
    if (resubscribe || limit_reached || stop_) context.TryCancel();
    const grpc::Status status = stream->Finish();
    {
      std::lock_guard lock(context_mutex_);
      active_context_ = nullptr;
    }
    first_stream = false;
    if (limit_reached || stop_) return true;
    if (status.error_code() == grpc::StatusCode::DEADLINE_EXCEEDED && clock::now() >= deadline) return true;
    if (resubscribe) {
      ++stats_.resubscribes;
      continue;
    }
    stats_.final_status = status.ok() ? "stream ended by the server"
                                      : "stream ended: " + std::to_string(status.error_code()) + " " + status.error_message();
    return false;
  }
  return true;
}

}  // namespace hapsim::viewer
