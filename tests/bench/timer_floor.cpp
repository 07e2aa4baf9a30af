// The host's own lateness floor: one thread sleeping to absolute 1 ms
// deadlines (clock_nanosleep, CLOCK_MONOTONIC, timer slack 1 ns as the tick
// workers set it) with nothing of hapsim running. Every late tick the
// capacity benchmark counts above this floor is the server's; below it, no
// server change can help. Run pinned to the core the server would use:
//
//   taskset -c 0 build/bin/bench_timer_floor
//
// Counters: wakes, the share more than one period late (a tick the server
// would count late), and the lateness p50 / p99 / max in microseconds.
// Second argument: a spin lead in microseconds — the thread sleeps to that
// long before each deadline and then polls the clock up to it (0: sleep all
// the way, the tick workers' way; 1000: never sleep, the core always busy).
// Whether a wake-up's lateness is the sleep's or the core's own stalls.
#include <benchmark/benchmark.h>
#include <sys/prctl.h>
#include <time.h>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace {

constexpr std::int64_t kPeriod_ns = 1'000'000;

std::int64_t MonotonicNs() {
  timespec t{};
  clock_gettime(CLOCK_MONOTONIC, &t);
  return std::int64_t{t.tv_sec} * 1'000'000'000 + t.tv_nsec;
}

void BM_TimerFloor(benchmark::State& state) {
  const auto wakes = static_cast<std::size_t>(state.range(0));
  const std::int64_t spin_lead_ns = 1000 * state.range(1);
  prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
  std::vector<std::int64_t> late_ns(wakes);
  for (auto _ : state) {
    std::int64_t due_ns = MonotonicNs() + kPeriod_ns;
    for (std::size_t k = 0; k < wakes; ++k) {
      const std::int64_t sleep_to_ns = due_ns - spin_lead_ns;
      if (MonotonicNs() < sleep_to_ns) {
        const timespec until{static_cast<time_t>(sleep_to_ns / 1'000'000'000),
                             static_cast<long>(sleep_to_ns % 1'000'000'000)};
        clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &until, nullptr);
      }
      while (MonotonicNs() < due_ns) {
      }
      late_ns[k] = MonotonicNs() - due_ns;
      due_ns += kPeriod_ns;  // absolute deadlines: a late wake does not shift the next ones
    }
  }
  std::vector<std::int64_t> sorted = late_ns;
  std::sort(sorted.begin(), sorted.end());
  const auto at = [&](double q) {
    return static_cast<double>(sorted[static_cast<std::size_t>(q * (wakes - 1))]) / 1e3;
  };
  const auto over_period = std::count_if(late_ns.begin(), late_ns.end(), [](std::int64_t l) { return l > kPeriod_ns; });
  state.counters["wakes"] = static_cast<double>(wakes);
  state.counters["late_over_1ms_pct"] = 100.0 * static_cast<double>(over_period) / static_cast<double>(wakes);
  state.counters["p50_us"] = at(0.5);
  state.counters["p99_us"] = at(0.99);
  state.counters["max_us"] = static_cast<double>(sorted.back()) / 1e3;
}
BENCHMARK(BM_TimerFloor)
    ->Args({10'000, 0})
    ->Args({10'000, 200})
    ->Args({10'000, 1000})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
