#include "hapsim/web/web_console.h"

#include <spdlog/spdlog.h>

#include <boost/beast/websocket/rfc6455.hpp>  // is_upgrade
#include <chrono>
#include <fstream>
#include <future>
#include <sstream>
#include <stdexcept>
#include <type_traits>

#include "hapsim/common/thread_setup.h"
#include "hapsim/web/static_files.h"
#include "web_console_impl.h"

namespace hapsim::web {

namespace {

constexpr auto kHttpIdleTimeout = std::chrono::seconds(30);

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
      StartWebSocketLink(std::move(stream_), std::move(request), console_);
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
