// LogLimiter: a flood of Cyclone log lines (a vanished interface: ~1000 failed
// sends a second) shows 20 lines per 10 s and says how many it hid.
#include "hapsim/dds/log_limit.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

namespace hapsim::dds {
namespace {

constexpr std::int64_t kMsNsLog = 1'000'000;

std::string Contents(std::FILE* f) {
  std::rewind(f);
  std::string text;
  char buffer[4096];
  std::size_t n;
  while ((n = std::fread(buffer, 1, sizeof buffer, f)) > 0) text.append(buffer, n);
  return text;
}

int CountOf(const std::string& text, const std::string& what) {
  int count = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++count;
  return count;
}

TEST(LogLimiter, AFloodOfAThousandLinesASecondShowsTwentyPerTenSecondsAndCountsTheRest) {
  std::FILE* out = std::tmpfile();
  ASSERT_NE(out, nullptr);
  LogLimiter limiter(out);
  // 25 s at 1 kHz: windows open at 0, 10 and 20 s.
  for (std::int64_t ms = 0; ms < 25'000; ++ms) limiter.Write("tev: udp write failed\n", ms * kMsNsLog);
  const std::string text = Contents(out);
  std::fclose(out);
  EXPECT_EQ(CountOf(text, "tev: udp write failed\n"), 3 * LogLimiter::kLinesPerWindow);
  EXPECT_EQ(CountOf(text, "counted, not shown"), 3);
  // The two windows that closed each report what they hid.
  EXPECT_EQ(CountOf(text, "hapsim: 9980 more Cyclone DDS log lines in the last 10 s were not shown\n"), 2);
  EXPECT_EQ(limiter.hidden_total(), 25'000u - 60u);
}

TEST(LogLimiter, AFewLinesPassUntouched) {
  std::FILE* out = std::tmpfile();
  ASSERT_NE(out, nullptr);
  LogLimiter limiter(out);
  limiter.Write("a\n", 0);
  limiter.Write("b\n", 5 * kMsNsLog);
  limiter.Write("c\n", 20'000 * kMsNsLog);
  EXPECT_EQ(Contents(out), "a\nb\nc\n");
  std::fclose(out);
  EXPECT_EQ(limiter.hidden_total(), 0u);
}

}  // namespace
}  // namespace hapsim::dds
