// Any bytes as the life of ViewerService.Subscribe streams, server side: two
// viewers watch one session, each through the real ViewerLink (rate limit,
// ack window, one write in flight, coalescing) and frame encoder, while the
// input decides what happens and in which order: the scene moves or is cut
// or reset, ticks publish snapshots, the pump offers the newest to the
// links, writes complete or fail, viewers ack (honestly or with any 64-bit
// value), cancel, or the session closes their streams.
//
// Input: two length-prefixed (1 byte) SubscribeRequests, then ops of 2 bytes
// (op, argument). A request CheckSubscribeRequest refuses must say why; that
// viewer does not join.
//
// Invariants, checked on every event:
//  - at most one write in flight per stream, and no write or second finish
//    after a stream finished (gRPC's rules for a bidi reactor);
//  - frames sent minus frames acknowledged never exceeds the ack window, and
//    two frames are never closer in time than 1 / max_rate_hz;
//  - every frame written is applied whole by the viewer's real MeshCache
//    (seq, topology version, edits), after which the viewer holds the
//    snapshot it was encoded from: the same live vertex and triangle slots,
//    the same triangles and parts, every position within half a quantum.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "fuzz_setup.h"
#include "grid_session.h"
#include "hapsim/api/viewer_service.h"
#include "hapsim/streaming/viewer_link.h"
#include "hapsim/viewer/mesh_cache.h"

namespace {

using namespace hapsim;

constexpr double kQuantum_m = 1e-5;

[[noreturn]] void Broken(const char* invariant) {
  std::fprintf(stderr, "invariant broken: %s\n", invariant);
  std::abort();
}

// The viewer's end of one stream: what gRPC would do with the reactor's
// calls, and the client's mesh cache fed with every frame written.
class Viewer final : public service::ViewerLink::Stream {
 public:
  Viewer(const v1::SubscribeRequest& request, std::uint64_t index)
      : link(std::make_shared<service::ViewerLink>("v" + std::to_string(index), request.max_rate_hz(), kQuantum_m,
                                                   request.ack_window())),
        window_(request.ack_window()),
        min_interval_ns_(request.max_rate_hz() > 0.0 ? std::llround(1e9 / request.max_rate_hz()) : 0) {
    link->Attach(this);
  }

  void StartFrameWrite(const v1::Frame* frame) override {
    if (finished_) Broken("a write after the stream finished");
    if (in_flight_) Broken("two writes in flight");
    in_flight_ = true;
    wire_ = frame->SerializeAsString();  // the bytes are fixed when the write starts
  }
  void FinishStream(const grpc::Status&) override {
    if (finished_) Broken("a stream finished twice");
    finished_ = true;
  }

  // The pump offered `snapshot` at `now_ns`; if the link wrote, the viewer
  // gets the frame and must then hold exactly that snapshot's mesh.
  void AfterOffer(service::ViewerLink::OfferResult result, const service::SceneSnapshot& snapshot,
                  std::int64_t now_ns) {
    if (result != service::ViewerLink::OfferResult::kSent) return;
    if (sent_ > 0 && now_ns - last_send_ns_ < min_interval_ns_) Broken("frames closer than 1 / max_rate_hz");
    last_send_ns_ = now_ns;
    if (window_ > 0 && OverdueBefore(now_ns) >= window_) Broken("sent with ack_window frames overdue");
    if (sent_ - acked_ >= service::ViewerLink::kMaxFramesInFlight) Broken("more frames in flight than the cap");
    sent_ns_.push_back(now_ns);
    ++sent_;
    v1::Frame frame;
    if (!frame.ParseFromString(wire_)) Broken("a frame that does not parse");
    std::string why;
    if (cache_.Apply(frame, &why) != viewer::ApplyResult::kApplied) {
      std::fprintf(stderr, "refused: %s\n", why.c_str());
      Broken("the viewer refused a frame the server sent");
    }
    if (!Holds(snapshot)) Broken("the viewer's mesh differs from the snapshot sent");
    applied_seq_ = cache_.last_seq();
  }

  void WriteDone(bool ok) {
    if (!in_flight_) return;  // gRPC calls OnWriteDone only after a write
    in_flight_ = false;
    link->OnWriteDone(ok);
  }
  // The client acknowledges `seq` (what it applied, or anything at all) at
  // now_ns, saying it held the frame held_us.
  void Ack(std::uint64_t seq, std::uint64_t held_us, std::int64_t now_ns) {
    // Acknowledged frames: seqs [0, acked_) once seq names a frame sent.
    if (seq < sent_) acked_ = std::max(acked_, seq + 1);
    link->OnAck(seq, held_us, now_ns);
  }
  void AckApplied(std::int64_t now_ns) {
    if (sent_ > 0) Ack(applied_seq_, 0, now_ns);
  }

  // Unacknowledged frames older than the link's measured round trip (with
  // the link's margins: a quarter of it and 2 ms); every one of them before
  // the link has measured it.
  std::uint64_t OverdueBefore(std::int64_t now_ns) const {
    const double rtt_s = link->link_round_trip_s();
    if (rtt_s < 0.0) return sent_ - acked_;
    const std::int64_t rtt_ns = std::llround(rtt_s * 1e9);
    const std::int64_t on_wire_ns = rtt_ns + rtt_ns / 4 + 2'000'000;
    std::uint64_t overdue = 0;
    for (std::uint64_t seq = acked_; seq < sent_; ++seq) overdue += now_ns - sent_ns_[seq] > on_wire_ns ? 1 : 0;
    return overdue;
  }

  // HAPSIM_FUZZ_TRACE=1: what one input did (to see that seeds reach sends).
  void Trace(int index) const {
    std::fprintf(stderr, "viewer %d: %llu frames sent and applied, %llu acknowledged, %zu triangles held\n", index,
                 static_cast<unsigned long long>(sent_), static_cast<unsigned long long>(acked_),
                 cache_.live_triangle_count());
  }

  std::shared_ptr<service::ViewerLink> link;

 private:
  bool Holds(const service::SceneSnapshot& s) const {
    if (cache_.vertex_slots() != s.vertex_slots || cache_.triangle_slots() != s.triangle_slots) return false;
    const Eigen::Matrix3Xd held = cache_.Vertices_m();
    for (std::uint32_t v = 0; v < s.vertex_slots; ++v) {
      if (cache_.vertex_live(v) != (s.vertex_live[v] != 0)) return false;
      if (!cache_.vertex_live(v)) continue;
      const double off = (held.col(v) - s.vertices_m.col(v)).cwiseAbs().maxCoeff();
      if (!(off <= 0.5 * kQuantum_m * (1 + 1e-9))) return false;
    }
    for (std::uint32_t t = 0; t < s.triangle_slots; ++t) {
      if (cache_.triangle_live(t) != (s.triangle_live[t] != 0)) return false;
      if (cache_.triangle_live(t) && (cache_.triangle(t) != s.triangles[t] || cache_.triangle_part(t) != s.triangle_parts[t]))
        return false;
    }
    return true;
  }

  viewer::MeshCache cache_;
  std::uint32_t window_;
  std::int64_t min_interval_ns_;
  bool in_flight_ = false, finished_ = false;
  std::string wire_;
  std::uint64_t sent_ = 0, acked_ = 0, applied_seq_ = 0;
  std::vector<std::int64_t> sent_ns_;  // by seq
  std::int64_t last_send_ns_ = 0;
};

// A cut-like edit: remove a live triangle and fill half of its place with a
// new vertex (the wound side), as the cutting scene's edits look to a viewer.
void Cut(fuzz::GridSession* session, std::uint8_t arg) {
  core::MeshTopology& topo = session->topology;
  const std::uint32_t t = arg % topo.Triangles().HighWater();
  if (!topo.Triangles().IsLive(t)) return;
  const auto corners = topo.TriangleVertices(t);
  topo.RemoveTriangle(t);
  const std::uint32_t v = topo.AddVertex();
  if (v == core::kNoSlot) return;
  session->x_m.col(v) = (session->x_m.col(corners[0]) + session->x_m.col(corners[1])) / 2 + Eigen::Vector3d(0, 0, -1e-4);
  if (topo.AddTriangle(corners[0], v, corners[2], 1) == core::kNoSlot) topo.RemoveVertex(v);
}

std::optional<v1::SubscribeRequest> TakeRequest(const std::uint8_t* data, std::size_t size, std::size_t* at) {
  if (*at >= size) return std::nullopt;
  const std::size_t length = std::min<std::size_t>(data[(*at)++], size - *at);
  v1::SubscribeRequest request;
  const bool parsed = request.ParseFromArray(data + *at, static_cast<int>(length));
  *at += length;
  if (!parsed) return std::nullopt;
  const grpc::Status status = service::CheckSubscribeRequest(request);
  if (!status.ok()) {
    if (status.error_code() != grpc::StatusCode::INVALID_ARGUMENT || status.error_message().empty())
      Broken("a refused SubscribeRequest without INVALID_ARGUMENT and a reason");
    return std::nullopt;
  }
  return request;
}

// Two viewers with ack windows 4 and 1, one at the session's rate and one at
// 30 Hz, then a mix of every op.
void WriteSeeds(const std::string& dir) {
  auto request = [](double rate_hz, std::uint32_t window) {
    v1::SubscribeRequest r;
    r.set_session_id("s");
    r.set_max_rate_hz(rate_hz);
    r.set_ack_window(window);
    const std::string bytes = r.SerializeAsString();
    return std::string(1, static_cast<char>(bytes.size())) + bytes;
  };
  const std::string viewers = request(0.0, 4) + request(30.0, 1);
  auto ops = [](std::initializer_list<int> list) {
    std::string s;
    for (const int b : list) s.push_back(static_cast<char>(b));
    return s;
  };
  // op: 0 move, 1 cut, 2 tick, 3 pump, 4 write done, 5 write failed, 6 ack
  // applied, 7 ack any, 8 cancel, 9 close, 10 reset; +16: the second viewer.
  std::ofstream(dir + "/steady", std::ios::binary)
      << viewers + ops({2, 10, 3, 40, 4, 0, 6, 0, 20, 0, 0, 140, 2, 0, 3, 20, 4, 0, 20, 0, 6, 0, 22, 0, 2, 0, 3, 40});
  std::ofstream(dir + "/cuts", std::ios::binary)
      << viewers + ops({2, 0, 3, 10, 4, 0, 6, 0, 1, 7, 1, 30, 2, 0, 3, 10, 4, 0, 1, 3, 1, 9, 1, 12, 2, 0, 3, 50, 4, 0,
                        20, 0, 6, 0, 22, 0, 10, 0, 2, 0, 3, 60, 4, 0, 20, 0});
  std::ofstream(dir + "/faults", std::ios::binary)
      << viewers + ops({2, 0, 3, 10, 7, 255, 23, 3, 5, 0, 2, 0, 3, 40, 24, 0, 8, 0, 25, 0, 1, 1, 2, 0, 3, 90, 9, 0});
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  hapsim::fuzz::SetUpServiceFuzzer(&WriteSeeds);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // Small logs (12 edits, history 8) so bursts of cuts outrun them.
  fuzz::GridSession session(12, 8);
  std::size_t at = 0;
  std::unique_ptr<Viewer> viewers[2];
  for (std::uint64_t k = 0; k < 2; ++k)
    if (const auto request = TakeRequest(data, size, &at)) viewers[k] = std::make_unique<Viewer>(*request, k);
  std::shared_ptr<const service::SceneSnapshot> ticked, latest;
  std::int64_t now_ns = 0;
  for (int steps = 0; at + 2 <= size && steps < 256; ++steps, at += 2) {
    const std::uint8_t op = data[at], arg = data[at + 1];
    Viewer* viewer = viewers[(op >> 4) & 1].get();
    switch (op & 0x0f) {
      case 0: {  // a vertex moves by -1.28..+1.27 mm
        const std::uint32_t v = arg % session.topology.Vertices().HighWater();
        session.x_m(2, v) += (static_cast<int>(arg) - 128) * 1e-5;
        break;
      }
      case 1: Cut(&session, arg); break;
      case 2:  // a tick publishes (the previous unpumped snapshot is dropped)
        if (auto s = session.Publish()) ticked = std::move(s);
        break;
      case 3: {  // the pump runs arg ms later: takes the newest, offers it to both
        now_ns += static_cast<std::int64_t>(arg) * 1'000'000;
        if (ticked) {
          session.history.Absorb(*ticked);
          latest = std::move(ticked);
          ticked.reset();
        }
        if (!latest) break;
        for (auto& v : viewers)
          if (v) v->AfterOffer(v->link->Offer(latest, session.history, now_ns), *latest, now_ns);
        break;
      }
      case 4: if (viewer) viewer->WriteDone(true); break;
      case 5: if (viewer) viewer->WriteDone(false); break;
      case 6:
        if (viewer) viewer->AckApplied(now_ns);
        break;
      case 7:  // a small seq (maybe not sent yet) or a huge one, held up to 25.5 ms (maybe longer than the trip)
        if (viewer) viewer->Ack(arg < 128 ? arg : (static_cast<std::uint64_t>(arg) << 56) | arg, arg * 100u, now_ns);
        break;
      case 8: if (viewer) viewer->link->OnCancelled(); break;
      case 9: if (viewer) viewer->link->Close(grpc::Status(grpc::StatusCode::NOT_FOUND, "session closed")); break;
      case 10: session.topology.Reset(); break;  // the trainee pressed reset: the topology restarts
      default: break;
    }
  }
  static const bool trace = std::getenv("HAPSIM_FUZZ_TRACE") != nullptr;
  for (int k = 0; k < 2; ++k) {
    if (!viewers[k]) continue;
    if (trace) viewers[k]->Trace(k);
    viewers[k]->link->Detach();
  }
  return 0;
}
