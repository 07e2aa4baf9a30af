// What recording the tick's distributions costs the 1 kHz tick: our
// lock-free TickHistogram against prometheus-cpp's Histogram::Observe (a
// mutex its Collect also holds), side by side, alone and while another
// thread scrapes the same histogram as fast as it can. A tick records three
// observations (work, lateness, pose to model).
//   build/bin/bench_frame_tick_histogram --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>
#include <prometheus/histogram.h>

#include <atomic>
#include <thread>

#include "hapsim/runtime/tick_histogram.h"

namespace {

prometheus::Histogram::BucketBoundaries Bounds() {
  return {hapsim::service::TickHistogram::kUpperBounds_s.begin(), hapsim::service::TickHistogram::kUpperBounds_s.end()};
}

// 37 us, 1.2 ms, 4 ms: spread over the buckets like real ticks.
constexpr std::int64_t kSamples_ns[] = {37'000, 1'200'000, 4'000'000};

void BM_TickHistogram(benchmark::State& state) {
  hapsim::service::TickHistogram h;
  std::atomic<bool> stop{false};
  std::thread scraper;
  if (state.range(0)) scraper = std::thread([&] { while (!stop) benchmark::DoNotOptimize(h.Read()); });
  for (auto _ : state) {
    for (const auto ns : kSamples_ns) h.Observe_ns(ns);
  }
  stop = true;
  if (scraper.joinable()) scraper.join();
  state.SetItemsProcessed(state.iterations() * 3);
}
BENCHMARK(BM_TickHistogram)->Arg(0)->Arg(1)->ArgName("scraping");

void BM_PrometheusHistogram(benchmark::State& state) {
  prometheus::Histogram h(Bounds());
  std::atomic<bool> stop{false};
  std::thread scraper;
  if (state.range(0)) scraper = std::thread([&] { while (!stop) benchmark::DoNotOptimize(h.Collect()); });
  for (auto _ : state) {
    for (const auto ns : kSamples_ns) h.Observe(static_cast<double>(ns) * 1e-9);
  }
  stop = true;
  if (scraper.joinable()) scraper.join();
  state.SetItemsProcessed(state.iterations() * 3);
}
BENCHMARK(BM_PrometheusHistogram)->Arg(0)->Arg(1)->ArgName("scraping");

}  // namespace

BENCHMARK_MAIN();
