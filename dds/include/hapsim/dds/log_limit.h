// Cyclone DDS logs every send that fails: when a network interface vanishes
// that is ~1000 lines a second, burying everything else in the log. Its log
// goes through a limiter instead: at most kLinesPerWindow lines per 10 s
// window, the rest counted and summed up in one line when the next window
// opens (a line that says more were hidden, so nothing is lost silently).
#pragma once
#include <cstdint>
#include <cstdio>
#include <mutex>
#include <string_view>

namespace hapsim::dds {

class LogLimiter {
 public:
  static constexpr int kLinesPerWindow = 20;
  static constexpr std::int64_t kWindowNs = 10'000'000'000;

  explicit LogLimiter(std::FILE* out) : out_(out) {}
  // One complete log line (with its newline), logged at now_ns.
  void Write(std::string_view line, std::int64_t now_ns);
  std::uint64_t hidden_total() const;

 private:
  mutable std::mutex mutex_;
  std::FILE* out_;
  std::int64_t window_start_ns_ = 0;
  bool started_ = false;
  int shown_in_window_ = 0;
  std::uint64_t hidden_in_window_ = 0, hidden_total_ = 0;
};

// Routes Cyclone's log (errors, warnings) through a LogLimiter on stderr.
// Once per process, before the first participant; later calls do nothing.
void LimitDdsLogRate();

}  // namespace hapsim::dds
