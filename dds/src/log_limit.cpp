#include "hapsim/dds/log_limit.h"

#include <dds/dds.h>

#include "hapsim/common/clock.h"

namespace hapsim::dds {

void LogLimiter::Write(std::string_view line, std::int64_t now_ns) {
  std::lock_guard lock(mutex_);
  if (!started_ || now_ns - window_start_ns_ >= kWindowNs) {
    if (hidden_in_window_ > 0) {
      std::fprintf(out_, "hapsim: %llu more Cyclone DDS log lines in the last %lld s were not shown\n",
                   static_cast<unsigned long long>(hidden_in_window_),
                   static_cast<long long>((now_ns - window_start_ns_) / 1'000'000'000));
    }
    started_ = true;
    window_start_ns_ = now_ns;
    shown_in_window_ = 0;
    hidden_in_window_ = 0;
  }
  if (shown_in_window_ < kLinesPerWindow) {
    std::fwrite(line.data(), 1, line.size(), out_);
    if (++shown_in_window_ == kLinesPerWindow) {
      std::fprintf(out_,
                   "hapsim: Cyclone DDS is logging fast; its further lines in these 10 s are counted, not shown\n");
    }
  } else {
    ++hidden_in_window_;
    ++hidden_total_;
  }
  std::fflush(out_);
}

std::uint64_t LogLimiter::hidden_total() const {
  std::lock_guard lock(mutex_);
  return hidden_total_;
}

namespace {
// Cyclone hands over the message after a header it has printed in front of
// it (hdrsize bytes) and a newline after it (at message[size]).
void LimitedSink(void* limiter, const dds_log_data_t* data) {
  const std::string_view line(data->message - data->hdrsize, data->hdrsize + data->size + 1);
  static_cast<LogLimiter*>(limiter)->Write(line, common::SteadyNowNs());
}
}  // namespace

void LimitDdsLogRate() {
  static std::once_flag once;
  std::call_once(once, [] {
    static LogLimiter limiter(stderr);  // lives as long as Cyclone may log
    dds_set_log_sink(&LimitedSink, &limiter);
  });
}

}  // namespace hapsim::dds
