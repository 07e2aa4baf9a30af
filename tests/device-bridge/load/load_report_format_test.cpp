// hapsim-load's summaries: the JSON carries every documented field with its
// value (times converted to ms), the CSV has one row per device plus total.
#include "hapsim/load/load_report_format.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <sstream>

namespace hapsim::bridge {
namespace {

LoadReport TwoDevices() {
  LoadReport r;
  r.rate_hz = 1000;
  r.elapsed_s = 4.0;
  LoadDeviceReport d;
  d.device_id = 1000;
  d.session = "load-0";
  d.flow.poses_sent = 4000;
  d.flow.pose_rate_hz = 1000.0;
  d.flow.models_received = 3990;
  d.flow.models_used = 3950;
  d.flow.round_trip_s.count = 3950;
  d.flow.round_trip_s.p50 = 0.00025;
  d.flow.round_trip_s.p99 = 0.0025;
  d.flow.round_trip_s.max = 0.011;
  d.flow.safety.warnings = 2;
  d.flow.safety.fades = 1;
  d.flow.safety.disarms = 1;
  d.flow.safety.clamped = 17;
  d.first_echo_seq = 3;
  d.last_echo_seq = 3998;
  d.final_watchdog = WatchdogState::kFresh;
  r.devices.push_back(d);
  d.device_id = 1001;
  d.session = "load-1";
  d.flow.safety = {};
  r.devices.push_back(d);
  r.total = SumDevices(r.devices);
  return r;
}

// The part of text from the first `from` up to the following `to` (or the end).
std::string Section(const std::string& text, const std::string& from, const std::string& to) {
  const auto begin = text.find(from);
  if (begin == std::string::npos) return "";
  return text.substr(begin, text.find(to, begin) - begin);
}

void ExpectContainsAll(const std::string& text, std::initializer_list<std::string> parts) {
  for (const auto& part : parts) EXPECT_NE(text.find(part), std::string::npos) << "missing: " << part << "\nin:\n" << text;
}

TEST(LoadReportJson, CarriesPerDeviceFieldsWithTimesInMilliseconds) {
  const auto d = nlohmann::json::parse(FormatLoadJson(TwoDevices()))["per_device"][0];
  EXPECT_EQ(d["device_id"], 1000);
  EXPECT_EQ(d["session"], "load-0");
  EXPECT_EQ(d["poses_sent"], 4000);
  EXPECT_DOUBLE_EQ(d["pose_rate_hz"].get<double>(), 1000.0);
  EXPECT_EQ(d["models_received"], 3990);
  EXPECT_EQ(d["models_used"], 3950);
  EXPECT_EQ(d["first_echo_seq"], 3);
  EXPECT_EQ(d["last_echo_seq"], 3998);
  EXPECT_EQ(d["echo_regressions"], 0);
  EXPECT_EQ(d["round_trip_ms"]["count"], 3950);
  EXPECT_DOUBLE_EQ(d["round_trip_ms"]["p50"].get<double>(), 0.25);
  EXPECT_DOUBLE_EQ(d["round_trip_ms"]["p99"].get<double>(), 2.5);
  EXPECT_DOUBLE_EQ(d["round_trip_ms"]["max"].get<double>(), 11.0);
  EXPECT_TRUE(d.contains("model_age_ms"));
  EXPECT_EQ(d["watchdog_warnings"], 2);
  EXPECT_EQ(d["watchdog_fades"], 1);
  EXPECT_EQ(d["watchdog_disarms"], 1);
  EXPECT_EQ(d["force_clamps"], 17);
  EXPECT_EQ(d["final_watchdog"], "fresh");
}

TEST(LoadReportJson, TotalSumsTheDevicesAndCountsTheDisarmedOnes) {
  const std::string total = Section(FormatLoadJson(TwoDevices()), "\"total\"", "\"per_device\"");
  ExpectContainsAll(total, {"\"devices\": 2", "\"devices_with_models\": 2", "\"devices_disarmed\": 1",
                            "\"poses_sent\": 8000", "\"pose_rate_hz\": 2000", "\"models_received\": 7980",
                            "\"watchdog_warnings\": 2", "\"force_clamps\": 17"});
}

TEST(LoadReportJson, ServerSessionsAppearOnlyWhenFetched) {
  LoadReport r = TwoDevices();
  EXPECT_EQ(FormatLoadJson(r).find("server_sessions"), std::string::npos);
  ServerSessionStats s;
  s.session_id = "load-0";
  s.late_ticks = 7;
  s.max_tick_lateness_s = 0.0015;
  s.device_streaming = true;
  r.server.push_back(s);
  ServerSessionStats missing;
  missing.session_id = "load-1";
  missing.error = "NOT_FOUND: no session";
  r.server.push_back(missing);
  ExpectContainsAll(Section(FormatLoadJson(r), "\"server_sessions\"", "\n}"),
                    {"\"late_ticks\": 7", "\"max_tick_lateness_ms\": 1.5", "\"device_streaming\": true",
                     "\"error\": \"NOT_FOUND: no session\""});
}

TEST(LoadReportJson, ParsesBackWithEveryDeviceAndServerSession) {
  LoadReport r = TwoDevices();
  r.server.push_back({});
  const auto json = nlohmann::json::parse(FormatLoadJson(r));  // throws if not JSON
  ASSERT_EQ(json["per_device"].size(), 2u);
  EXPECT_EQ(json["per_device"][1]["device_id"], 1001);
  EXPECT_EQ(json["server_sessions"].size(), 1u);
  EXPECT_EQ(json["total"]["devices"], 2);
}

// A session id with quotes, a backslash and a newline round-trips; an
// empty percentile (NaN) is null, not a token a JSON reader chokes on.
TEST(LoadReportJson, EscapesStringsAndWritesNonFiniteNumbersAsNull) {
  LoadReport r = TwoDevices();
  r.devices[0].session = "a\"b\\c\n";
  r.devices[0].flow.round_trip_s.p50 = std::nan("");
  const auto json = nlohmann::json::parse(FormatLoadJson(r));
  EXPECT_EQ(json["per_device"][0]["session"], "a\"b\\c\n");
  EXPECT_TRUE(json["per_device"][0]["round_trip_ms"]["p50"].is_null());
}

TEST(LoadReportCsv, OneRowPerDevicePlusTotalAllWithTheHeadersColumnCount) {
  const std::string csv = FormatLoadCsv(TwoDevices());
  std::istringstream in(csv);
  std::string line;
  std::vector<std::string> lines;
  while (std::getline(in, line)) lines.push_back(line);
  ASSERT_EQ(lines.size(), 4u);
  const auto columns = [](const std::string& l) { return std::count(l.begin(), l.end(), ','); };
  for (const auto& l : lines) EXPECT_EQ(columns(l), columns(lines[0])) << l;
  EXPECT_EQ(lines[1].rfind("1000,load-0,4000,", 0), 0u);
  EXPECT_EQ(lines[3].rfind("total,", 0), 0u);
}

}  // namespace
}  // namespace hapsim::bridge
