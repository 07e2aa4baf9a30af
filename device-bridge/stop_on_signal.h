// SIGINT/SIGTERM set a stop flag from a helper thread (asio), so a servo
// loop finishes its tick, leaves the motors at zero force and prints its
// report instead of dying mid-tick. For the executables' main() only.
#pragma once
#include <atomic>
#include <csignal>
#include <thread>

#include <asio/io_context.hpp>
#include <asio/signal_set.hpp>
#include <spdlog/spdlog.h>

namespace hapsim::bridge {

class StopOnSignal {
 public:
  explicit StopOnSignal(std::atomic<bool>* stop) : signals_(io_, SIGINT, SIGTERM) {
    signals_.async_wait([stop](const std::error_code& ec, int signal) {
      if (!ec) spdlog::info("signal {} received: stopping", signal);
      *stop = true;
    });
    thread_ = std::thread([this] { io_.run(); });
  }
  ~StopOnSignal() {
    io_.stop();
    thread_.join();
  }
  StopOnSignal(const StopOnSignal&) = delete;
  StopOnSignal& operator=(const StopOnSignal&) = delete;

 private:
  asio::io_context io_;
  asio::signal_set signals_;
  std::thread thread_;
};

}  // namespace hapsim::bridge
