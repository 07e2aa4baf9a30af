// What the browser console costs on the wire: N console connections to a
// running hapsim-server --web-listen, each watching a class (as a browser's
// tiles do), the first also viewing one trainee and acknowledging every
// frame at once (as a browser that keeps up does). Prints one JSON object:
// statuses and frames received, their sizes, the view's frame rate.
// With --grpc ADDRESS the N clients are native consoles instead (what
// hapsim-viewer --class does): each its own gRPC channel with a WatchClass
// stream, the first also a Subscribe stream; sizes are then the protobuf
// messages' (without HTTP/2's framing).
// Run by tests/bench/web_console.sh (docs/performance.md, "The web console").
//
//   bench_web_probe (--port P | --grpc HOST:PORT) --token-file F --class C
//                   [--view SESSION] [--clients N] [--seconds S] [--tls-ca CA]
#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "hapsim/v1/session.grpc.pb.h"
#include "hapsim/v1/viewer.grpc.pb.h"
#include "hapsim/viewer/connection.h"
#include "server/web/console_client.h"

namespace {

using hapsim::v1::ConsoleEvent;
using Clock = std::chrono::steady_clock;

struct Options {
  int port = 0, clients = 1;
  double seconds = 10.0;
  std::string token, class_name, view, tls_ca, grpc;
};

struct Tally {
  std::uint64_t statuses = 0, status_bytes = 0, status_max = 0;
  std::uint64_t frames = 0, keyframes = 0, delta_bytes = 0, delta_max = 0, keyframe_bytes = 0, vertices = 0;
  bool connected = false;

  void CountFrame(const hapsim::v1::Frame& frame, std::uint64_t bytes) {
    ++frames;
    if (frame.has_keyframe()) {
      ++keyframes;
      keyframe_bytes += bytes;
      vertices = static_cast<std::uint64_t>(frame.keyframe().positions_q_size() / 3);
    } else {
      delta_bytes += bytes;
      delta_max = std::max(delta_max, bytes);
    }
  }
  void CountStatus(std::uint64_t bytes) {
    ++statuses;
    status_bytes += bytes;
    status_max = std::max(status_max, bytes);
  }
};

Clock::time_point EndOf(const Options& o) {
  return Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(o.seconds));
}

template <class Client>
void Watch(Client& client, const Options& o, bool view, Tally* t) {
  if (!client.Connect(o.port)) return;
  t->connected = true;
  client.Hello(o.token);
  hapsim::v1::ConsoleRequest watch;
  watch.mutable_watch_class()->set_class_name(o.class_name);
  watch.mutable_watch_class()->set_rate_hz(10);
  client.Send(watch);
  if (view) {
    hapsim::v1::ConsoleRequest open;
    open.mutable_open_view()->set_session_id(o.view);
    open.mutable_open_view()->set_ack_window(4);
    client.Send(open);
  }
  const auto end = EndOf(o);
  while (Clock::now() < end) {
    const auto event = client.Next(std::chrono::seconds(2));
    if (!event) break;
    const std::uint64_t bytes = event->ByteSizeLong();
    if (event->has_class_status()) {
      t->CountStatus(bytes);
    } else if (event->has_frame()) {
      t->CountFrame(event->frame(), bytes);
      hapsim::v1::ConsoleRequest ack;
      ack.mutable_ack()->set_applied_seq(event->frame().seq());
      client.Send(ack);
    }
  }
}

// A native console: a WatchClass stream at 10 Hz and, for the first, a
// Subscribe stream acknowledging every frame at once.
void WatchNative(const Options& o, bool view, Tally* t) {
  hapsim::viewer::Connection connection;
  connection.address = o.grpc;
  connection.token = o.token;
  connection.tls_ca_file = o.tls_ca;
  grpc::ChannelArguments args;
  args.SetInt("grpc.use_local_subchannel_pool", 1);  // a channel of its own, as another machine's
  const auto channel = hapsim::viewer::MakeChannel(connection, args);
  const auto end = EndOf(o);
  const auto deadline = std::chrono::system_clock::now() +  // gRPC's deadlines are on the system clock
                        std::chrono::duration_cast<std::chrono::system_clock::duration>(end - Clock::now());
  std::thread frames;
  grpc::ClientContext view_context;
  if (view) {
    frames = std::thread([&] {
      auto viewers = hapsim::v1::ViewerService::NewStub(channel);
      hapsim::viewer::AddToken(&view_context, o.token);
      view_context.set_deadline(deadline);
      auto stream = viewers->Subscribe(&view_context);
      hapsim::v1::ViewerMessage hello;
      hello.mutable_subscribe()->set_session_id(o.view);
      hello.mutable_subscribe()->set_ack_window(4);
      stream->Write(hello);
      hapsim::v1::Frame frame;
      while (Clock::now() < end && stream->Read(&frame)) {
        t->CountFrame(frame, frame.ByteSizeLong());
        hapsim::v1::ViewerMessage ack;
        ack.mutable_ack()->set_applied_seq(frame.seq());
        stream->Write(ack);
      }
      view_context.TryCancel();  // the deadline passed: stop the stream here, not at the server's leisure
    });
  }
  auto sessions = hapsim::v1::SessionService::NewStub(channel);
  grpc::ClientContext context;
  hapsim::viewer::AddToken(&context, o.token);
  context.set_deadline(deadline);
  hapsim::v1::WatchClassRequest request;
  request.set_class_name(o.class_name);
  request.set_rate_hz(10);
  auto reader = sessions->WatchClass(&context, request);
  hapsim::v1::ClassStatus status;
  while (reader->Read(&status)) {
    t->connected = true;
    t->CountStatus(status.ByteSizeLong());
  }
  if (frames.joinable()) frames.join();
}

bool Parse(int argc, char** argv, Options* o) {
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i], v = argv[i + 1];
    if (k == "--port")
      o->port = std::stoi(v);
    else if (k == "--clients")
      o->clients = std::stoi(v);
    else if (k == "--seconds")
      o->seconds = std::stod(v);
    else if (k == "--class")
      o->class_name = v;
    else if (k == "--view")
      o->view = v;
    else if (k == "--tls-ca")
      o->tls_ca = v;
    else if (k == "--grpc")
      o->grpc = v;
    else if (k == "--token-file")
      std::getline(std::ifstream(v) >> std::ws, o->token);
    else
      return false;
  }
  return (o->port > 0) != !o->grpc.empty() && o->clients >= 1 && !o->token.empty();
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (argc % 2 == 0 || !Parse(argc, argv, &o)) {
    std::fprintf(stderr,
                 "usage: bench_web_probe (--port P | --grpc HOST:PORT) --token-file F --class C [--view SESSION] "
                 "[--clients N] [--seconds S] [--tls-ca CA]\n");
    return 2;
  }
  std::vector<Tally> tallies(static_cast<std::size_t>(o.clients));
  std::vector<std::thread> threads;
  for (int i = 0; i < o.clients; ++i) {
    threads.emplace_back([&, i] {
      const bool view = i == 0 && !o.view.empty();
      if (!o.grpc.empty()) {
        WatchNative(o, view, &tallies[static_cast<std::size_t>(i)]);
      } else if (o.tls_ca.empty()) {
        hapsim::web::test::PlainClient client;
        Watch(client, o, view, &tallies[static_cast<std::size_t>(i)]);
      } else {
        hapsim::web::test::TlsClient client(o.tls_ca);
        Watch(client, o, view, &tallies[static_cast<std::size_t>(i)]);
      }
    });
  }
  for (auto& t : threads) t.join();
  Tally sum;
  int connected = 0;
  for (const auto& t : tallies) {
    connected += t.connected;
    sum.statuses += t.statuses;
    sum.status_bytes += t.status_bytes;
    sum.status_max = std::max(sum.status_max, t.status_max);
  }
  const Tally& v = tallies[0];
  const std::uint64_t deltas = v.frames - v.keyframes;
  std::printf(
      "{\"clients\": %d, \"connected\": %d, \"seconds\": %.1f, \"statuses\": %llu, \"status_bytes_mean\": %.0f, "
      "\"status_bytes_max\": %llu, \"view_frames\": %llu, \"view_fps\": %.1f, \"view_vertices\": %llu, "
      "\"keyframe_bytes\": %llu, \"delta_bytes_mean\": %.0f, \"delta_bytes_max\": %llu}\n",
      o.clients, connected, o.seconds, static_cast<unsigned long long>(sum.statuses),
      sum.statuses ? static_cast<double>(sum.status_bytes) / static_cast<double>(sum.statuses) : 0.0,
      static_cast<unsigned long long>(sum.status_max), static_cast<unsigned long long>(v.frames),
      static_cast<double>(v.frames) / o.seconds, static_cast<unsigned long long>(v.vertices),
      static_cast<unsigned long long>(v.keyframes ? v.keyframe_bytes / v.keyframes : 0),
      deltas ? static_cast<double>(v.delta_bytes) / static_cast<double>(deltas) : 0.0,
      static_cast<unsigned long long>(v.delta_max));
  return connected == o.clients ? 0 : 1;
}
