#include <boost/beast/websocket.hpp>

#include "websocket_link.h"

namespace hapsim::web {

void StartWebSocketLink(PlainStream&& stream, http::request<http::string_body> request, WebConsole::Impl* console) {
  std::make_shared<WebSocketLink<PlainStream>>(std::move(stream), console)->Run(std::move(request));
}

}  // namespace hapsim::web
