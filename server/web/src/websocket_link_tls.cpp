#include <boost/beast/websocket/ssl.hpp>

#include "websocket_link.h"

namespace hapsim::web {

void StartWebSocketLink(TlsStream&& stream, http::request<http::string_body> request, WebConsole::Impl* console) {
  std::make_shared<WebSocketLink<TlsStream>>(std::move(stream), console)->Run(std::move(request));
}

}  // namespace hapsim::web
