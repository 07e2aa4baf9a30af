// A console client for the tests: Beast's WebSocket over plain TCP or TLS,
// speaking hapsim.v1.ConsoleRequest / ConsoleEvent as the web app does.
#pragma once
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/ssl.hpp>
#include <boost/beast/websocket.hpp>
#include <boost/beast/websocket/ssl.hpp>
#include <chrono>
#include <optional>
#include <string>

#include "hapsim/v1/console.pb.h"

namespace hapsim::web::test {

namespace beast = boost::beast;
namespace net = boost::asio;
namespace ssl = net::ssl;
using tcp = net::ip::tcp;

template <class Stream>
class ConsoleClient {
 public:
  // Plain TCP.
  ConsoleClient() : ws_(io_) {}
  // TLS, trusting `ca_file`.
  explicit ConsoleClient(const std::string& ca_file) : tls_(std::in_place, ssl::context::tls_client), ws_(io_, *tls_) {
    tls_->load_verify_file(ca_file);
    tls_->set_verify_mode(ssl::verify_peer);
  }

  // Connects and upgrades to the console's WebSocket; false (and why) on failure.
  bool Connect(int port, std::string* why = nullptr) {
    try {
      tcp::resolver resolver(io_);
      beast::get_lowest_layer(ws_).connect(resolver.resolve("127.0.0.1", std::to_string(port)));
      if constexpr (!std::is_same_v<Stream, beast::tcp_stream>) {
        ws_.next_layer().handshake(ssl::stream_base::client);
      }
      ws_.handshake("localhost:" + std::to_string(port), "/ws");
      ws_.binary(true);
      return true;
    } catch (const std::exception& e) {
      if (why) *why = e.what();
      return false;
    }
  }

  void Send(const hapsim::v1::ConsoleRequest& request) { SendBytes(request.SerializeAsString()); }
  void SendBytes(const std::string& bytes) { ws_.write(net::buffer(bytes)); }
  void Hello(const std::string& token) {
    hapsim::v1::ConsoleRequest r;
    r.mutable_hello()->set_token(token);
    Send(r);
  }

  // The next event, or nullopt if the connection closed or nothing came
  // within `timeout` (the connection is then unusable).
  std::optional<hapsim::v1::ConsoleEvent> Next(std::chrono::milliseconds timeout = std::chrono::seconds(5)) {
    beast::flat_buffer buffer;
    beast::error_code result = net::error::timed_out;
    bool done = false;
    ws_.async_read(buffer, [&](beast::error_code ec, std::size_t) {
      result = ec;
      done = true;
    });
    io_.restart();
    io_.run_for(timeout);
    if (!done) {
      beast::get_lowest_layer(ws_).cancel();
      io_.restart();
      io_.run_for(std::chrono::seconds(1));
      return std::nullopt;
    }
    if (result) return std::nullopt;
    hapsim::v1::ConsoleEvent event;
    const auto data = buffer.cdata();
    if (!event.ParseFromArray(data.data(), static_cast<int>(data.size()))) return std::nullopt;
    ++received_;
    bytes_ += data.size();
    if (event.has_class_status()) {  // shown at once, as the web app does
      hapsim::v1::ConsoleRequest ack;
      ack.mutable_status_ack()->set_seq(event.class_status().seq());
      Send(ack);
    }
    return event;
  }

  // The next event of one kind, skipping others (class statuses, frames).
  std::optional<hapsim::v1::ConsoleEvent> NextOf(hapsim::v1::ConsoleEvent::EventCase kind,
                                                 std::chrono::milliseconds timeout = std::chrono::seconds(5)) {
    const auto until = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < until) {
      auto event =
          Next(std::chrono::duration_cast<std::chrono::milliseconds>(until - std::chrono::steady_clock::now()));
      if (!event) return std::nullopt;
      if (event->event_case() == kind) return event;
    }
    return std::nullopt;
  }

  std::uint64_t received() const { return received_; }
  std::uint64_t bytes() const { return bytes_; }

 private:
  net::io_context io_;
  std::optional<ssl::context> tls_;
  beast::websocket::stream<Stream> ws_;
  std::uint64_t received_ = 0, bytes_ = 0;
};

using PlainClient = ConsoleClient<beast::tcp_stream>;
using TlsClient = ConsoleClient<beast::ssl_stream<beast::tcp_stream>>;

}  // namespace hapsim::web::test
