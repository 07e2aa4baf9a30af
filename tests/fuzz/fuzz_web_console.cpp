// Any bytes at the browser console's endpoint of a whole server (ServerApp
// with a class, its web console on 127.0.0.1), in one of two ways picked by
// the first byte:
//  - even: WebSocket messages, as a browser page would send them. The
//    second byte picks a hello sent first (none, the instructor's, the
//    observer's, the trainee's or a garbage token); the rest is messages,
//    each a 2-byte little-endian length and that many bytes (any bytes: a
//    ConsoleRequest or not). Then a marker call (ListScenes, id
//    kMarkerCallId) and the events read until its reply or the close.
//  - odd: the rest as raw bytes on a TCP connection (an HTTP request, a
//    WebSocket upgrade and frames, or garbage), then the write side shut
//    and the answer read until the server closes.
//
// Invariants, after every input: whatever the server sent on the WebSocket
// parsed as a ConsoleEvent, and a refusal was the last thing it sent; the
// server then still serves a fresh connection — the instructor's hello is
// welcomed and a ListSessions call answers OK with every class session —
// so one browser's mistake never takes the console, or the class, down.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "../server/web/console_client.h"
#include "../test_dds_domain.h"
#include "fuzz_setup.h"
#include "hapsim/app/server_app.h"

namespace {

using namespace hapsim;
using web::test::PlainClient;
using namespace std::chrono_literals;

constexpr std::uint32_t kMarkerCallId = 0xFFFFFFFFu;
constexpr std::size_t kMaxMessages = 64;

const char* const kTokens[] = {"", "fuzz-instructor-token-1", "fuzz-observer-token-22", "fuzz-trainee-token-333",
                               "garbage"};

constexpr const char* kClassConfig = R"(
[[class]]
name = "fuzzclass"
[[class.session]]
id = "t1"
scene = "tissue_block"
trainee = "ann"
[[class.session]]
id = "t2"
scene = "tissue_block"
trainee = "bob"
[[token]]
name = "dr"
role = "instructor"
class = "fuzzclass"
token = "fuzz-instructor-token-1"
[[token]]
name = "visitor"
role = "observer"
class = "fuzzclass"
token = "fuzz-observer-token-22"
[[token]]
name = "ann"
role = "trainee"
class = "fuzzclass"
sessions = ["t1"]
token = "fuzz-trainee-token-333"
)";

[[noreturn]] void Broken(const std::string& invariant) {
  std::fprintf(stderr, "invariant broken: %s\n", invariant.c_str());
  std::abort();
}

service::ServerApp& TheServer() {
  static service::ServerApp* app = [] {  // lives for the process (the fuzzer exits without unwinding)
    const auto root = std::filesystem::temp_directory_path() / ("hapsim-fuzz-web-" + std::to_string(::getpid()));
    std::filesystem::create_directories(root);
    std::ofstream(root / "index.html") << "<!doctype html><title>console</title>";
    service::ServerOptions o;
    o.listen_address = "127.0.0.1:0";
    o.dds.domain_id = test::ClaimTestDdsDomain();
    o.web_listen_address = "127.0.0.1:0";
    o.web_root = root.string();
    o.classes = service::ParseClassConfig(kClassConfig, "fuzz");
    return new service::ServerApp(o);
  }();
  return *app;
}

v1::ConsoleRequest Marker() {
  v1::ConsoleRequest r;
  r.mutable_call()->set_id(kMarkerCallId);
  r.mutable_call()->mutable_list_scenes();
  return r;
}

// A PushScenario rebuilds both class sessions; a vessel takes up to a
// minute to build under ASan. The call's path is the same for every scene
// (building scenes under any parameters is fuzz_session_service's), so a
// push names the cheap tissue_block with its defaults; other bytes pass as
// they are.
std::string CheapPush(std::string message) {
  v1::ConsoleRequest r;
  if (!r.ParseFromString(message) || !r.has_call() || !r.call().has_push_scenario()) return message;
  auto* push = r.mutable_call()->mutable_push_scenario();
  push->set_scene("tissue_block");
  push->clear_params();
  return r.SerializeAsString();
}

// Sends the messages, then the marker, and reads until its reply or the close.
void PlayMessages(const std::uint8_t* data, std::size_t size) {
  PlainClient client;
  std::string why;
  if (!client.Connect(TheServer().web_port(), &why)) Broken("cannot connect to the console: " + why);
  const std::size_t hello = size > 0 ? data[0] % std::size(kTokens) : 0;
  if (size > 0) ++data, --size;
  try {
    if (hello > 0) client.Hello(kTokens[hello]);
    for (std::size_t n = 0; n < kMaxMessages && size >= 2; ++n) {
      const std::size_t length = std::min<std::size_t>(data[0] | (data[1] << 8), size - 2);
      client.SendBytes(CheapPush(std::string(reinterpret_cast<const char*>(data + 2), length)));
      data += 2 + length, size -= 2 + length;
    }
    client.Send(Marker());
  } catch (const std::exception&) {
    return;  // the server closed the connection while we wrote: a refusal, read below would find nothing
  }
  bool refused = false;
  for (;;) {
    auto event = client.Next(10s);
    if (!event) break;  // closed (or nothing for 10 s, which the health check below then judges)
    if (refused) Broken("an event after a refusal: " + event->DebugString());
    if (event->has_refused()) refused = true;
    if (event->has_reply() && event->reply().id() == kMarkerCallId) break;
  }
}

// Raw bytes on a TCP connection: write, shut the write side, read to the close.
void PlayRaw(const std::uint8_t* data, std::size_t size) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) Broken("no socket");
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<std::uint16_t>(TheServer().web_port()));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) Broken("cannot connect (raw)");
  timeval timeout{.tv_sec = 10, .tv_usec = 0};
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  ::setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &timeout, sizeof timeout);
  for (std::size_t sent = 0; sent < size;) {
    const ssize_t n = ::send(fd, data + sent, size - sent, MSG_NOSIGNAL);
    if (n <= 0) break;  // the server closed on what it had read: fine
    sent += static_cast<std::size_t>(n);
  }
  ::shutdown(fd, SHUT_WR);
  char buffer[4096];
  while (::recv(fd, buffer, sizeof buffer, 0) > 0) {
  }
  ::close(fd);
}

// A fresh instructor connection is welcomed and lists every class session.
void CheckHealthy() {
  PlainClient client;
  std::string why;
  if (!client.Connect(TheServer().web_port(), &why)) Broken("the console refuses new connections: " + why);
  client.Hello(kTokens[1]);
  auto welcome = client.Next(10s);
  if (!welcome || !welcome->has_welcome()) Broken("no welcome after the input");
  v1::ConsoleRequest list;
  list.mutable_call()->set_id(1);
  list.mutable_call()->mutable_list_sessions();
  client.Send(list);
  auto reply = client.NextOf(v1::ConsoleEvent::kReply, 10s);
  if (!reply || reply->reply().code() != 0) Broken("ListSessions failed after the input");
  int class_sessions = 0;
  for (const auto& s : reply->reply().sessions().sessions())
    class_sessions += s.session_id() == "t1" || s.session_id() == "t2";
  if (class_sessions != 2) Broken("a class session is gone after the input");
}

void WriteSeed(const std::string& dir, const std::string& name, const std::string& bytes) {
  std::ofstream(dir + "/" + name, std::ios::binary) << bytes;
}

std::string Framed(const v1::ConsoleRequest& r) {
  const std::string body = r.SerializeAsString();
  return std::string{static_cast<char>(body.size() & 0xff), static_cast<char>(body.size() >> 8)} + body;
}

void WriteSeeds(const std::string& dir) {
  std::filesystem::create_directories(dir);
  v1::ConsoleRequest watch;
  watch.mutable_watch_class()->set_class_name("fuzzclass");
  watch.mutable_watch_class()->set_rate_hz(50);
  v1::ConsoleRequest open;
  open.mutable_open_view()->set_session_id("t1");
  open.mutable_open_view()->set_ack_window(2);
  v1::ConsoleRequest ack;
  ack.mutable_ack()->set_applied_seq(1);
  ack.mutable_ack()->set_held_us(500);
  v1::ConsoleRequest status_ack;
  status_ack.mutable_status_ack()->set_seq(1);
  v1::ConsoleRequest pause;
  pause.mutable_call()->set_id(2);
  pause.mutable_call()->mutable_pause_session()->set_session_id("t1");
  v1::ConsoleRequest resume;
  resume.mutable_call()->set_id(3);
  resume.mutable_call()->mutable_resume_session()->set_session_id("t1");
  v1::ConsoleRequest trials;
  trials.mutable_call()->set_id(4);
  trials.mutable_call()->mutable_get_trials()->set_class_name("fuzzclass");
  v1::ConsoleRequest close;
  close.mutable_close_view();
  v1::ConsoleRequest hello;
  hello.mutable_hello()->set_token(kTokens[1]);
  const std::string ws = std::string(1, '\0');
  for (char who : {'\1', '\2', '\3'}) {
    WriteSeed(dir, std::string("instructor-watch-view-") + char('0' + who),
              ws + who + Framed(watch) + Framed(open) + Framed(ack) + Framed(status_ack) + Framed(close));
    WriteSeed(dir, std::string("calls-") + char('0' + who), ws + who + Framed(pause) + Framed(resume) + Framed(trials));
  }
  WriteSeed(dir, "hello-in-messages", ws + '\0' + Framed(hello) + Framed(watch));
  WriteSeed(dir, "garbage-token", ws + '\4' + Framed(watch));
  WriteSeed(dir, "not-protobuf", ws + '\1' + std::string("\x05\x00\xff\xff\xff\xff\xff", 7));
  const std::string raw = std::string(1, '\1');
  WriteSeed(dir, "raw-get-index", raw + "GET / HTTP/1.1\r\nHost: localhost\r\n\r\n");
  WriteSeed(dir, "raw-get-outside", raw + "GET /../%2e%2e/etc/passwd HTTP/1.1\r\nHost: localhost\r\n\r\n");
  // An upgrade, then one masked binary frame (mask 0): a hello with token "x".
  const char frame[] = "\x82\x85\x00\x00\x00\x00\x0a\x03\x0a\x01\x78";
  WriteSeed(dir, "raw-upgrade",
            raw +
                "GET /ws HTTP/1.1\r\nHost: localhost\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
                "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n" +
                std::string(frame, sizeof frame - 1));
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  fuzz::SetUpServiceFuzzer(WriteSeeds);
  TheServer();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  // libFuzzer's timeout alarm (SIGALRM, every second) would interrupt this
  // thread's blocking connect and writes (EINTR); held back while the input
  // plays. Every wait here is bounded by its own timeout (10 s) instead.
  sigset_t alarm, before;
  sigemptyset(&alarm);
  sigaddset(&alarm, SIGALRM);
  pthread_sigmask(SIG_BLOCK, &alarm, &before);
  if (data[0] % 2 == 0) {
    PlayMessages(data + 1, size - 1);
  } else {
    PlayRaw(data + 1, size - 1);
  }
  CheckHealthy();
  pthread_sigmask(SIG_SETMASK, &before, nullptr);
  return 0;
}
