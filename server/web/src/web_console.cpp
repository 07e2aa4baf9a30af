#include "hapsim/web/web_console.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>
#include <boost/beast/websocket.hpp>
#include <boost/beast/websocket/ssl.hpp>
#include <chrono>
#include <deque>
#include <fstream>
#include <future>
#include <mutex>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <type_traits>
#include <vector>

#include "class_watch_hub.h"
#include "console_session.h"
#include "hapsim/common/thread_setup.h"
#include "hapsim/web/static_files.h"

namespace hapsim::web {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
namespace ssl = net::ssl;
using tcp = net::ip::tcp;
using PlainStream = beast::tcp_stream;
using TlsStream = beast::ssl_stream<beast::tcp_stream>;

namespace {
constexpr std::size_t kMaxRequestBytes = 64 * 1024;  // one console message; HTTP headers and body
constexpr auto kHttpIdleTimeout = std::chrono::seconds(30);
}  // namespace

// An open WebSocket, as the endpoint sees it when it stops.
class LiveConnection {
 public:
  virtual ~LiveConnection() = default;
  virtual void CloseNow() = 0;  // I/O thread
};

struct WebConsole::Impl {
  // Everything the connections use is declared before the I/O context: the
  // handlers it still holds when it is destroyed destroy connections.
  WebConsoleOptions options;
  OpenCalls open_calls;
  std::unique_ptr<ClassWatchHub> class_watches;
  ConsoleServices services;
  std::optional<ssl::context> tls;
  int bound_port = 0;
  int websockets = 0;                               // I/O thread only
  std::vector<std::weak_ptr<LiveConnection>> live;  // I/O thread only
  std::mutex stop_mutex;
  bool stopped = false;
  net::io_context io{1};
  tcp::acceptor acceptor{io};
  std::thread thread;

  void Listen();
  void Accept();
  std::string ServeFile(const std::string& target, http::status* status, std::string* content_type) const;
};

namespace {

// One browser's WebSocket: the console protocol's transport. Writes are
// queued and sent one at a time on the I/O thread.
template <class Stream>
class WebSocketLink final : public ConsoleTransport,
                            public LiveConnection,
                            public std::enable_shared_from_this<WebSocketLink<Stream>> {
 public:
  WebSocketLink(Stream&& stream, WebConsole::Impl* console) : ws_(std::move(stream)), console_(console) {
    ++console_->websockets;
  }
  ~WebSocketLink() override { --console_->websockets; }

  void Run(http::request<http::string_body> request) {
    ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    ws_.read_message_max(kMaxRequestBytes);
    ws_.binary(true);
    ws_.async_accept(request, [self = this->shared_from_this()](beast::error_code ec) { self->OnAccept(ec); });
  }

  void Send(std::shared_ptr<const std::string> bytes, std::function<void(bool sent)> on_sent) override {
    net::post(ws_.get_executor(),
              [self = this->shared_from_this(), bytes = std::move(bytes), on_sent = std::move(on_sent)]() mutable {
                if (self->closed_) {
                  on_sent(false);
                  return;
                }
                self->queue_.push_back({std::move(bytes), std::move(on_sent)});
                if (!self->writing_) self->WriteNext();
              });
  }

  void Close() override {
    net::post(ws_.get_executor(), [self = this->shared_from_this()] {
      self->closing_ = true;
      if (!self->writing_) self->CloseHandshake();
    });
  }

  void CloseNow() override {
    Closed();
    beast::error_code ignored;
    beast::get_lowest_layer(ws_).socket().close(ignored);
  }

 private:
  struct Outgoing {
    std::shared_ptr<const std::string> bytes;
    std::function<void(bool)> on_sent;
  };

  void OnAccept(beast::error_code ec) {
    if (ec) return;
    auto& live = console_->live;
    live.erase(std::remove_if(live.begin(), live.end(), [](const auto& w) { return w.expired(); }), live.end());
    live.push_back(this->shared_from_this());
    session_ = std::make_shared<ConsoleSession>(console_->services, this->shared_from_this());
    Read();
  }

  void Read() {
    ws_.async_read(buffer_, [self = this->shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec) {
        self->Closed();
        return;
      }
      const auto data = self->buffer_.cdata();
      self->session_->OnMessage(std::string_view(static_cast<const char*>(data.data()), data.size()));
      self->buffer_.consume(self->buffer_.size());
      if (!self->closed_) self->Read();
    });
  }

  void WriteNext() {
    writing_ = true;
    ws_.async_write(net::buffer(*queue_.front().bytes),
                    [self = this->shared_from_this()](beast::error_code ec, std::size_t) { self->OnWrite(ec); });
  }

  void OnWrite(beast::error_code ec) {
    writing_ = false;
    Outgoing done = std::move(queue_.front());
    queue_.pop_front();
    done.on_sent(!ec);
    if (ec) {
      Closed();
    } else if (!closed_ && !queue_.empty()) {
      WriteNext();
    } else if (!closed_ && closing_) {
      CloseHandshake();
    }
  }

  void CloseHandshake() {
    if (closed_) return;
    ws_.async_close(websocket::close_code::normal,
                    [self = this->shared_from_this()](beast::error_code) { self->Closed(); });
  }

  // The connection is over: every queued message is reported unsent (but
  // the one being written, whose handler reports it) and the streams end.
  void Closed() {
    if (closed_) return;
    closed_ = true;
    const std::size_t keep = writing_ ? 1 : 0;
    while (queue_.size() > keep) {
      auto on_sent = std::move(queue_.back().on_sent);
      queue_.pop_back();
      on_sent(false);
    }
    if (session_) session_->OnClosed();
    session_.reset();
  }

  websocket::stream<Stream> ws_;
  WebConsole::Impl* console_;
  beast::flat_buffer buffer_;
  std::shared_ptr<ConsoleSession> session_;
  std::deque<Outgoing> queue_;
  bool writing_ = false, closing_ = false, closed_ = false;
};

// One HTTP connection: the web app's files, or the upgrade to the console's
// WebSocket at /ws.
template <class Stream>
class HttpExchange final : public std::enable_shared_from_this<HttpExchange<Stream>> {
 public:
  static constexpr bool kTls = std::is_same_v<Stream, TlsStream>;

  HttpExchange(Stream&& stream, WebConsole::Impl* console) : stream_(std::move(stream)), console_(console) {}

  void Run() {
    beast::get_lowest_layer(stream_).expires_after(kHttpIdleTimeout);
    if constexpr (kTls) {
      stream_.async_handshake(ssl::stream_base::server, [self = this->shared_from_this()](beast::error_code ec) {
        if (!ec) self->Read();
      });
    } else {
      Read();
    }
  }

 private:
  void Read() {
    parser_.emplace();
    parser_->header_limit(static_cast<std::uint32_t>(kMaxRequestBytes));
    parser_->body_limit(kMaxRequestBytes);
    beast::get_lowest_layer(stream_).expires_after(kHttpIdleTimeout);
    http::async_read(stream_, buffer_, *parser_, [self = this->shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec) {
        self->Shutdown();
        return;
      }
      self->OnRequest(self->parser_->release());
    });
  }

  void OnRequest(http::request<http::string_body> request) {
    if (websocket::is_upgrade(request)) {
      if (request.target() != "/ws") return Respond(request, http::status::not_found, "no WebSocket here: use /ws\n");
      if (console_->websockets >= console_->options.max_connections) {
        return Respond(request, http::status::service_unavailable,
                       "too many console connections (" + std::to_string(console_->options.max_connections) + ")\n");
      }
      beast::get_lowest_layer(stream_).expires_never();  // the WebSocket keeps its own timeouts
      std::make_shared<WebSocketLink<Stream>>(std::move(stream_), console_)->Run(std::move(request));
      return;
    }
    if (request.method() != http::verb::get && request.method() != http::verb::head) {
      return Respond(request, http::status::method_not_allowed, "GET only\n");
    }
    http::status status = http::status::ok;
    std::string content_type;
    std::string body = console_->ServeFile(std::string(request.target()), &status, &content_type);
    Respond(request, status, std::move(body), content_type);
  }

  void Respond(const http::request<http::string_body>& request, http::status status, std::string body,
               const std::string& content_type = "text/plain; charset=utf-8") {
    auto response = std::make_shared<http::response<http::string_body>>(status, request.version());
    response->set(http::field::server, "hapsim");
    response->set(http::field::content_type, content_type);
    response->set(http::field::cache_control, "no-cache");
    response->set("X-Content-Type-Options", "nosniff");
    response->set("Referrer-Policy", "no-referrer");
    response->set("Content-Security-Policy",
                  "default-src 'self'; connect-src 'self'; img-src 'self' data: blob:; style-src 'self' "
                  "'unsafe-inline'; frame-ancestors 'none'");
    response->keep_alive(request.keep_alive());
    const bool head = request.method() == http::verb::head;
    response->body() = std::move(body);
    response->prepare_payload();
    if (head) response->body().clear();
    http::async_write(stream_, *response,
                      [self = this->shared_from_this(), response](beast::error_code ec, std::size_t) {
                        if (ec || response->need_eof()) {
                          self->Shutdown();
                        } else {
                          self->Read();
                        }
                      });
  }

  void Shutdown() {
    beast::error_code ignored;
    if constexpr (kTls) {
      beast::get_lowest_layer(stream_).expires_after(std::chrono::seconds(2));
      stream_.async_shutdown([self = this->shared_from_this()](beast::error_code) {});
    } else {
      stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
    }
  }

  Stream stream_;
  WebConsole::Impl* console_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
};

// "host:port" -> endpoint (IPv6 hosts in brackets).
tcp::endpoint ParseListenAddress(const std::string& address, net::io_context& io) {
  const auto colon = address.rfind(':');
  if (colon == std::string::npos || colon + 1 == address.size()) {
    throw std::runtime_error("web console address '" + address + "' is not HOST:PORT");
  }
  std::string host = address.substr(0, colon);
  if (host.size() >= 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
  const std::string port = address.substr(colon + 1);
  tcp::resolver resolver(io);
  beast::error_code ec;
  const auto results = resolver.resolve(host, port, tcp::resolver::passive | tcp::resolver::numeric_service, ec);
  if (ec || results.empty()) {
    throw std::runtime_error("web console address '" + address + "': " + (ec ? ec.message() : "no address"));
  }
  return results.begin()->endpoint();
}

}  // namespace

std::string WebConsole::Impl::ServeFile(const std::string& target, http::status* status,
                                        std::string* content_type) const {
  const auto file = ResolveStaticFile(options.root_dir, target);
  if (!file) {
    *status = http::status::not_found;
    *content_type = "text/plain; charset=utf-8";
    return "not found\n";
  }
  std::ifstream in(file->path, std::ios::binary);
  std::ostringstream body;
  body << in.rdbuf();
  if (!in) {
    *status = http::status::internal_server_error;
    *content_type = "text/plain; charset=utf-8";
    return "cannot read the file\n";
  }
  *content_type = file->content_type;
  return std::move(body).str();
}

void WebConsole::Impl::Listen() {
  const tcp::endpoint endpoint = ParseListenAddress(options.listen_address, io);
  beast::error_code ec;
  acceptor.open(endpoint.protocol(), ec);
  if (!ec) acceptor.set_option(net::socket_base::reuse_address(true), ec);
  if (!ec) acceptor.bind(endpoint, ec);
  if (!ec) acceptor.listen(net::socket_base::max_listen_connections, ec);
  if (ec) {
    throw std::runtime_error("web console cannot listen on " + options.listen_address + ": " + ec.message() +
                             " (choose another with --web-listen)");
  }
  bound_port = acceptor.local_endpoint().port();
}

void WebConsole::Impl::Accept() {
  acceptor.async_accept([this](beast::error_code ec, tcp::socket socket) {
    if (ec) {
      if (ec != net::error::operation_aborted) Accept();  // e.g. out of file descriptors: keep serving
      return;
    }
    socket.set_option(tcp::no_delay(true), ec);
    if (tls) {
      std::make_shared<HttpExchange<TlsStream>>(TlsStream(std::move(socket), *tls), this)->Run();
    } else {
      std::make_shared<HttpExchange<PlainStream>>(PlainStream(std::move(socket)), this)->Run();
    }
    Accept();
  });
}

WebConsole::WebConsole(const WebConsoleOptions& options, std::shared_ptr<grpc::Channel> channel,
                       const service::AccessPolicy* policy)
    : impl_(std::make_unique<Impl>()) {
  Impl& w = *impl_;
  w.options = options;
  w.class_watches = std::make_unique<ClassWatchHub>(channel, &w.open_calls);
  w.services =
      ConsoleServices{std::move(channel), w.class_watches.get(), policy, options.server_version, &w.open_calls};
  if (options.tls_cert_file.empty() != options.tls_key_file.empty()) {
    throw std::runtime_error("the web console's TLS needs both a certificate and its key");
  }
  if (!options.tls_cert_file.empty()) {
    try {
      w.tls.emplace(ssl::context::tls_server);
      w.tls->set_options(ssl::context::default_workarounds | ssl::context::no_sslv2 | ssl::context::no_sslv3 |
                         ssl::context::no_tlsv1 | ssl::context::no_tlsv1_1 | ssl::context::single_dh_use);
      w.tls->use_certificate_chain_file(options.tls_cert_file);
      w.tls->use_private_key_file(options.tls_key_file, ssl::context::pem);
      if (!options.tls_client_ca_file.empty()) {
        w.tls->load_verify_file(options.tls_client_ca_file);
        w.tls->set_verify_mode(ssl::verify_peer | ssl::verify_fail_if_no_peer_cert);
      }
    } catch (const boost::system::system_error& e) {
      throw std::runtime_error("web console TLS files (" + options.tls_cert_file + ", " + options.tls_key_file +
                               "): " + e.what());
    }
  }
  w.Listen();
  w.Accept();
  w.thread = std::thread([&w] {
    common::NameThisThread("hapsim-web");
    // Browsers can wait a few milliseconds; a due tick on the same core cannot.
    common::LowerThisThreadPriority();
    w.io.run();
  });
}

WebConsole::~WebConsole() { Stop(); }

int WebConsole::bound_port() const { return impl_->bound_port; }
bool WebConsole::tls() const { return impl_->tls.has_value(); }

void WebConsole::Stop() {
  Impl& w = *impl_;
  {
    std::lock_guard lock(w.stop_mutex);
    if (w.stopped) return;
    w.stopped = true;
  }
  // Every connection is closed on the I/O thread, and that has happened
  // before the calls are waited for and the thread stops (a connection never
  // closed would keep its session, and the session it, alive for ever).
  std::promise<void> closed;
  net::post(w.io, [&w, &closed] {
    beast::error_code ignored;
    w.acceptor.close(ignored);
    for (const auto& weak : w.live) {
      if (auto connection = weak.lock()) connection->CloseNow();
    }
    w.live.clear();
    closed.set_value();
  });
  if (closed.get_future().wait_for(std::chrono::seconds(3)) != std::future_status::ready) {
    spdlog::warn("web console: its I/O thread did not close the connections within 3 s; stopping anyway");
  }
  if (!w.open_calls.WaitForNone(std::chrono::seconds(3))) {
    spdlog::warn("web console: gRPC calls of its connections still open after 3 s; stopping anyway");
  }
  w.io.stop();
  if (w.thread.joinable()) w.thread.join();
}

}  // namespace hapsim::web
