// What a console session sends through: the WebSocket of one browser. Any
// thread may call it; the transport serialises the writes on its I/O thread.
#pragma once
#include <functional>
#include <memory>
#include <string>

namespace hapsim::web {

class ConsoleTransport {
 public:
  virtual ~ConsoleTransport() = default;
  // Sends one binary message. on_sent runs exactly once, on the I/O thread:
  // true once the message is written, false if the connection closed first.
  virtual void Send(std::shared_ptr<const std::string> bytes, std::function<void(bool sent)> on_sent) = 0;
  // Closes the connection after what is already queued.
  virtual void Close() = 0;
};

}  // namespace hapsim::web
