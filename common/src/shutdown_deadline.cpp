#include "hapsim/common/shutdown_deadline.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>

namespace hapsim::common {

ShutdownDeadline::ShutdownDeadline(std::string program) : program_(std::move(program)) {}

ShutdownDeadline::~ShutdownDeadline() {
  {
    std::lock_guard lock(mutex_);
    disarmed_ = true;
  }
  disarmed_cv_.notify_all();
  if (watcher_.joinable()) watcher_.join();
}

void ShutdownDeadline::Arm(double seconds) {
  std::lock_guard lock(mutex_);
  if (watcher_.joinable() || disarmed_) return;
  watcher_ = std::thread([this, seconds] { Watch(seconds); });
}

void ShutdownDeadline::Watch(double seconds) {
  std::unique_lock lock(mutex_);
  const auto limit =
      std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(seconds));
  if (disarmed_cv_.wait_for(lock, limit, [this] { return disarmed_; })) return;
  const int code = exit_code_;
  std::fprintf(stderr,
               "%s: teardown did not finish within %.1f s (the network interface may be gone; DDS waits for "
               "packets that cannot come): exiting with code %d without it\n",
               program_.c_str(), seconds, code);
  std::fflush(stdout);
  std::fflush(stderr);
  ::_exit(code);
}

}  // namespace hapsim::common
