// What the browser console costs on the wire: N console connections to a
// running hapsim-server --web-listen, each watching a class (as a browser's
// tiles do), the first also viewing one trainee and acknowledging every
// frame at once (as a browser that keeps up does). Prints one JSON object:
// statuses and frames received, their sizes, the view's frame rate.
// Run by tests/bench/web_console.sh (docs/performance.md, "The web console").
//
//   bench_web_probe --port P --token-file F --class C [--view SESSION]
//                   [--clients N] [--seconds S] [--tls-ca CA]
#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "server/web/console_client.h"

namespace {

using hapsim::v1::ConsoleEvent;
using Clock = std::chrono::steady_clock;

struct Options {
  int port = 0, clients = 1;
  double seconds = 10.0;
  std::string token, class_name, view, tls_ca;
};

struct Tally {
  std::uint64_t statuses = 0, status_bytes = 0, status_max = 0;
  std::uint64_t frames = 0, keyframes = 0, delta_bytes = 0, delta_max = 0, keyframe_bytes = 0, vertices = 0;
  bool connected = false;
};

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
  const auto end = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(o.seconds));
  while (Clock::now() < end) {
    const auto event = client.Next(std::chrono::seconds(2));
    if (!event) break;
    const std::uint64_t bytes = event->ByteSizeLong();
    if (event->has_class_status()) {
      ++t->statuses;
      t->status_bytes += bytes;
      t->status_max = std::max(t->status_max, bytes);
    } else if (event->has_frame()) {
      ++t->frames;
      if (event->frame().has_keyframe()) {
        ++t->keyframes;
        t->keyframe_bytes += bytes;
        t->vertices = static_cast<std::uint64_t>(event->frame().keyframe().positions_q_size() / 3);
      } else {
        t->delta_bytes += bytes;
        t->delta_max = std::max(t->delta_max, bytes);
      }
      hapsim::v1::ConsoleRequest ack;
      ack.mutable_ack()->set_applied_seq(event->frame().seq());
      client.Send(ack);
    }
  }
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
    else if (k == "--token-file")
      std::getline(std::ifstream(v) >> std::ws, o->token);
    else
      return false;
  }
  return o->port > 0 && o->clients >= 1 && !o->token.empty();
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (argc % 2 == 0 || !Parse(argc, argv, &o)) {
    std::fprintf(stderr,
                 "usage: bench_web_probe --port P --token-file F --class C [--view SESSION] [--clients N] "
                 "[--seconds S] [--tls-ca CA]\n");
    return 2;
  }
  std::vector<Tally> tallies(static_cast<std::size_t>(o.clients));
  std::vector<std::thread> threads;
  for (int i = 0; i < o.clients; ++i) {
    threads.emplace_back([&, i] {
      const bool view = i == 0 && !o.view.empty();
      if (o.tls_ca.empty()) {
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
