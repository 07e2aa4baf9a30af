// The console's WebSocket: one browser's transport for the console protocol
// (console_session.h), over plain TCP (websocket_link_plain.cpp) or TLS
// (websocket_link_tls.cpp) — one file each, because Beast's WebSocket code
// for one stream type takes a minute or two to compile (under ASan) and the
// two then build side by side.
#pragma once
#include <algorithm>
#include <boost/beast/websocket.hpp>
#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <utility>

#include "web_console_impl.h"

namespace hapsim::web {

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

}  // namespace hapsim::web
