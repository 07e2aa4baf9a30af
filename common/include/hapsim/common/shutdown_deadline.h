// A bound on a process's teardown. Some teardown can wait on the network
// forever: Cyclone DDS wakes its receive threads by sending each a packet,
// and when the network interface has vanished that packet never comes, so
// deleting the participant blocks. A process arms the deadline once its
// real work is done (the device's force at zero, the report printed); if
// teardown has not finished when it passes, the process says so and exits
// with the code it meant to return, skipping what is left (the kernel closes
// its sockets). Destroying the deadline (teardown done in time) disarms it.
#pragma once
#include <atomic>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

namespace hapsim::common {

class ShutdownDeadline {
 public:
  // program: names the process in the message.
  explicit ShutdownDeadline(std::string program);
  ~ShutdownDeadline();
  ShutdownDeadline(const ShutdownDeadline&) = delete;
  ShutdownDeadline& operator=(const ShutdownDeadline&) = delete;

  // From now, teardown may take at most `seconds`; then the process exits
  // with exit_code(). Arming twice keeps the first deadline.
  void Arm(double seconds);
  void set_exit_code(int code) { exit_code_ = code; }
  int exit_code() const { return exit_code_; }

 private:
  void Watch(double seconds);

  std::string program_;
  std::atomic<int> exit_code_{0};
  std::mutex mutex_;
  std::condition_variable disarmed_cv_;
  bool disarmed_ = false;
  std::thread watcher_;
};

}  // namespace hapsim::common
