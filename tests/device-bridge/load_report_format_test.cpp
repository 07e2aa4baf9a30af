// hapsim-load's summaries: the JSON carries every documented field with its
// value (times converted to ms), the CSV has one row per device plus total.
#include "hapsim/bridge/load_report_format.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <sstream>

#include <gtest/gtest.h>

#include "hapsim/bridge/json_writer.h"

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
  const std::string device0 = Section(FormatLoadJson(TwoDevices()), "\"device_id\": 1000", "\"device_id\": 1001");
  ExpectContainsAll(device0, {"\"session\": \"load-0\"", "\"poses_sent\": 4000", "\"pose_rate_hz\": 1000",
                              "\"models_received\": 3990", "\"models_used\": 3950", "\"first_echo_seq\": 3",
                              "\"last_echo_seq\": 3998", "\"echo_regressions\": 0",
                              "\"round_trip_ms\": {\n        \"count\": 3950,\n        \"p50\": 0.25,\n"
                              "        \"p99\": 2.5,\n        \"max\": 11,",
                              "\"model_age_ms\"", "\"watchdog_warnings\": 2", "\"watchdog_fades\": 1",
                              "\"watchdog_disarms\": 1", "\"force_clamps\": 17", "\"final_watchdog\": \"fresh\""});
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

TEST(LoadReportJson, BracesAndBracketsBalance) {
  LoadReport r = TwoDevices();
  r.server.push_back({});
  const std::string json = FormatLoadJson(r);
  EXPECT_EQ(std::count(json.begin(), json.end(), '{'), std::count(json.begin(), json.end(), '}'));
  EXPECT_EQ(std::count(json.begin(), json.end(), '['), std::count(json.begin(), json.end(), ']'));
  EXPECT_EQ(json.front(), '{');
  EXPECT_EQ(json.substr(json.size() - 2), "}\n");
}

TEST(JsonWriter, EscapesStringsAndWritesNonFiniteNumbersAsNull) {
  JsonWriter w;
  w.BeginObject();
  w.Field("text", "a\"b\\c\n");
  w.Field("bad", std::nan(""));
  w.BeginArray("empty");
  w.EndArray();
  w.EndObject();
  EXPECT_EQ(w.text(), "{\n  \"text\": \"a\\\"b\\\\c\\u000a\",\n  \"bad\": null,\n  \"empty\": []\n}\n");
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
