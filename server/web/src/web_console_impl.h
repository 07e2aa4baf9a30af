// What the console endpoint's halves share: web_console.cpp (listening,
// HTTP, the web app's files) and websocket_link.h (the console's WebSocket,
// one file per stream type). Boost.Beast's HTTP and WebSocket code are the
// slowest files of the build to compile; apart, they compile side by side.
#pragma once
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>
#include <cstddef>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "class_watch_hub.h"
#include "console_session.h"
#include "hapsim/web/web_console.h"

namespace hapsim::web {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
namespace ssl = net::ssl;
using tcp = net::ip::tcp;
using PlainStream = beast::tcp_stream;
using TlsStream = beast::ssl_stream<beast::tcp_stream>;

inline constexpr std::size_t kMaxRequestBytes = 64 * 1024;  // one console message; HTTP headers and body

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

// An upgraded connection becomes the console's WebSocket (websocket_link.h);
// `request` is the upgrade request. I/O thread.
void StartWebSocketLink(PlainStream&& stream, http::request<http::string_body> request, WebConsole::Impl* console);
void StartWebSocketLink(TlsStream&& stream, http::request<http::string_body> request, WebConsole::Impl* console);

}  // namespace hapsim::web
