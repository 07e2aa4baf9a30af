#include "hapsim/viewer/viewer_client.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>

#include "hapsim/common/clock.h"

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

namespace {

std::chrono::steady_clock::time_point DeadlineAfter(double seconds) {
  using Clock = std::chrono::steady_clock;
  if (seconds <= 0.0) return Clock::time_point::max();
  return Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
}

hapsim::v1::ViewerMessage SubscribeMessage(const ViewerOptions& options) {
  hapsim::v1::ViewerMessage hello;
  auto* request = hello.mutable_subscribe();
  request->set_session_id(options.session);
  request->set_max_rate_hz(options.max_rate_hz);
  request->set_viewer_name(options.name);
  request->set_ack_window(options.ack_window);
  return hello;
}

}  // namespace

bool ViewerClient::Run() {
  const Clock::time_point deadline = DeadlineAfter(options_.max_seconds);
  if (!WaitForServer()) return false;
  bool first_stream = true;
  while (!stop_) {
    grpc::ClientContext context;
    const StreamResult result = RunStream(&context, deadline, first_stream);
    first_stream = false;
    if (result.end == StreamEnd::kLimit || stop_) return true;
    if (result.status.error_code() == grpc::StatusCode::DEADLINE_EXCEEDED && Clock::now() >= deadline) return true;
    if (result.end == StreamEnd::kResubscribe) {
      ++stats_.resubscribes;
      continue;
    }
    stats_.final_status = result.status.ok() ? "stream ended by the server"
                                             : "stream ended: " + std::to_string(result.status.error_code()) + " " +
                                                   result.status.error_message();
    return false;
  }
  return true;
}

bool ViewerClient::WaitForServer() {
  if (channel_->WaitForConnected(std::chrono::system_clock::now() +
                                 std::chrono::milliseconds(static_cast<long>(options_.connect_timeout_s * 1e3)))) {
    return true;
  }
  stats_.final_status = "cannot connect to the server within " + std::to_string(options_.connect_timeout_s) + " s";
  return false;
}

void ViewerClient::SetActiveContext(grpc::ClientContext* context) {
  std::lock_guard lock(context_mutex_);
  active_context_ = context;
}

ViewerClient::StreamResult ViewerClient::RunStream(grpc::ClientContext* context, Clock::time_point deadline,
                                                   bool first_stream) {
  AddToken(context, options_.token);
  if (deadline != Clock::time_point::max()) {
    context->set_deadline(std::chrono::system_clock::now() + (deadline - Clock::now()));
  }
  SetActiveContext(context);
  if (stop_) context->TryCancel();
  auto stream = stub_->Subscribe(context);
  stream->Write(SubscribeMessage(options_));  // a failure shows up as the stream's final status
  decoder_.ForgetMesh();
  StreamEnd end = StreamEnd::kByServer;
  hapsim::v1::Frame wire;
  hapsim::v1::ViewerMessage ack;
  while (stream->Read(&wire)) {
    const std::int64_t received_ns = common::SteadyNowNs();
    if (!TakeFrame(wire, first_stream)) {
      end = StreamEnd::kResubscribe;
      break;
    }
    // Acknowledge what is applied (or deliberately dropped): the server sends
    // at most ack_window frames ahead of this.
    // With the time spent here, so the server tells the link's round trip from this viewer's work.
    ack.mutable_ack()->set_applied_seq(wire.seq());
    ack.mutable_ack()->set_held_us(
        static_cast<std::uint64_t>(std::max<std::int64_t>(0, common::SteadyNowNs() - received_ns) / 1000));
    stream->Write(ack);
    if (options_.max_frames > 0 && stats_.frames >= options_.max_frames) {
      end = StreamEnd::kLimit;
      break;
    }
  }
  if (end != StreamEnd::kByServer || stop_) context->TryCancel();
  StreamResult result{end, stream->Finish()};
  SetActiveContext(nullptr);
  return result;
}

bool ViewerClient::TakeFrame(const hapsim::v1::Frame& wire, bool first_stream) {
  const ViewerFrame& frame = decoder_.Decode(wire);
  CountFrame(wire, frame);
  if (options_.on_received) options_.on_received(frame);
  const bool injected_loss =
      first_stream && options_.debug_drop_seq >= 0 && wire.seq() == static_cast<std::uint64_t>(options_.debug_drop_seq);
  if (injected_loss) return true;
  std::string why;
  const ApplyResult result = decoder_.ApplyMesh(wire, &why);
  if (result != ApplyResult::kApplied) {
    CountRefusal(result);
    spdlog::warn("frame {} refused ({}): {}; resubscribing for a keyframe", wire.seq(), ToString(result), why);
    return false;
  }
  if (options_.recorder) options_.recorder->Write(wire);
  if (options_.on_frame) options_.on_frame(frame, decoder_.mesh());
  return true;
}

void ViewerClient::CountFrame(const hapsim::v1::Frame& wire, const ViewerFrame& frame) {
  if (stats_.frames == 0) stats_.first_sim_time_s = frame.sim_time_s;
  ++stats_.frames;
  stats_.bytes += wire.ByteSizeLong();
  if (frame.keyframe)
    ++stats_.keyframes;
  else
    ++stats_.deltas;
  stats_.last_sim_time_s = frame.sim_time_s;
  stats_.peak_tool_force_N = std::max(stats_.peak_tool_force_N, frame.peak_force_N);
}

void ViewerClient::CountRefusal(ApplyResult result) {
  if (result == ApplyResult::kGap) ++stats_.gaps;
  if (result == ApplyResult::kTopologyMismatch) ++stats_.topology_mismatches;
  if (result == ApplyResult::kMalformed) ++stats_.malformed;
}

}  // namespace hapsim::viewer
