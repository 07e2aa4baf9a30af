#include "hapsim/load/load_report_format.h"

#include <cstdarg>
#include <cstdio>
#include <nlohmann/json.hpp>

namespace hapsim::bridge {

namespace {

constexpr double kMs = 1e3;

std::string Printf(const char* format, ...) __attribute__((format(printf, 1, 2)));
std::string Printf(const char* format, ...) {
  char buf[512];
  va_list args;
  va_start(args, format);
  std::vsnprintf(buf, sizeof buf, format, args);
  va_end(args);
  return buf;
}

unsigned long long U(std::uint64_t v) { return static_cast<unsigned long long>(v); }

using Json = nlohmann::ordered_json;  // members in the order written, as people read them

// nlohmann::json writes a non-finite number as null, like an empty percentile's NaN.
Json PercentilesMs(const common::Percentiles& p) {
  return {{"count", p.count}, {"p50", p.p50 * kMs}, {"p99", p.p99 * kMs}, {"max", p.max * kMs}, {"mean", p.mean * kMs}};
}

void AddFlow(Json& j, const LoadFlow& f) {
  j["poses_sent"] = f.poses_sent;
  j["pose_write_failures"] = f.pose_write_failures;
  j["pose_rate_hz"] = f.pose_rate_hz;
  j["models_received"] = f.models_received;
  j["models_used"] = f.models_used;
  j["echo_regressions"] = f.echo_regressions;
  j["models_unused"] = f.models_unused;
  j["round_trip_ms"] = PercentilesMs(f.round_trip_s);
  j["model_age_ms"] = PercentilesMs(f.model_age_s);
  j["physics_age_ms"] = PercentilesMs(f.physics_age_s);
  j["watchdog_delay_warnings"] = f.safety.delay_warnings;
  j["watchdog_warnings"] = f.safety.warnings;
  j["watchdog_fades"] = f.safety.fades;
  j["watchdog_disarms"] = f.safety.disarms;
  j["force_clamps"] = f.safety.clamped;
  j["force_rise_limited"] = f.safety.rate_limited;
  j["non_finite_forces"] = f.safety.non_finite;
}

Json DeviceJson(const LoadDeviceReport& d) {
  Json j = {{"device_id", d.device_id}, {"session", d.session}};
  AddFlow(j, d.flow);
  j["first_echo_seq"] = d.first_echo_seq;
  j["last_echo_seq"] = d.last_echo_seq;
  j["final_watchdog"] = ToString(d.final_watchdog);
  j["peak_force_n"] = d.peak_force_N;
  return j;
}

Json TotalJson(const LoadTotals& t) {
  Json j = {
      {"devices", t.devices}, {"devices_with_models", t.devices_with_models}, {"devices_disarmed", t.devices_disarmed}};
  AddFlow(j, t.flow);
  return j;
}

Json ServerJson(const ServerSessionStats& s) {
  if (!s.error.empty()) return {{"session_id", s.session_id}, {"error", s.error}};
  return {{"session_id", s.session_id},
          {"ticks", s.ticks},
          {"late_ticks", s.late_ticks},
          {"device_clocked_ticks", s.device_clocked_ticks},
          {"max_tick_lateness_ms", s.max_tick_lateness_s * kMs},
          {"poses_received", s.poses_received},
          {"poses_rejected", s.poses_rejected},
          {"poses_from_other_devices", s.poses_from_other_devices},
          {"force_models_sent", s.force_models_sent},
          {"owning_device_id", s.owning_device_id},
          {"device_streaming", s.device_streaming}};
}

std::string TableRow(const std::string& device, const std::string& session, const LoadFlow& f,
                     const std::string& echo) {
  const common::Percentiles &rtt = f.round_trip_s, &age = f.model_age_s;
  return Printf("%-8s %-14s %8.1f %8llu  %6.3f %6.3f %7.3f  %6.3f %6.3f %7.3f  %-22s %5llu %5llu %6llu %7llu\n",
                device.c_str(), session.c_str(), f.pose_rate_hz, U(f.models_received), rtt.p50 * kMs, rtt.p99 * kMs,
                rtt.max * kMs, age.p50 * kMs, age.p99 * kMs, age.max * kMs, echo.c_str(), U(f.safety.warnings),
                U(f.safety.fades), U(f.safety.disarms), U(f.safety.clamped));
}

// The CSV columns after device_id,session (one function, so the total row
// cannot drift from the device rows).
std::string CsvFlowAndEcho(const LoadFlow& f, std::uint64_t first_echo, std::uint64_t last_echo,
                           const char* final_watchdog) {
  const common::Percentiles &rtt = f.round_trip_s, &age = f.model_age_s;
  return Printf("%llu,%.3f,%llu,%llu,%llu,%llu,%llu,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%llu,%llu,%llu,%llu,%s\n",
                U(f.poses_sent), f.pose_rate_hz, U(f.models_received), U(f.models_used), U(first_echo),
                U(last_echo), U(f.echo_regressions), rtt.p50 * kMs, rtt.p99 * kMs, rtt.max * kMs, age.p50 * kMs,
                age.p99 * kMs, age.max * kMs, U(f.safety.warnings), U(f.safety.fades), U(f.safety.disarms),
                U(f.safety.clamped), final_watchdog);
}

}  // namespace

std::string FormatLoadTable(const LoadReport& r) {
  std::string out = Printf("hapsim-load: %zu devices, %.2f s at %.0f Hz\n", r.devices.size(), r.elapsed_s, r.rate_hz);
  out += Printf("%-8s %-14s %8s %8s  %-22s  %-22s  %-22s %5s %5s %6s %7s\n", "device", "session", "poses/s",
                "models", "round trip p50/p99/max", "model age p50/p99/max", "echoed seq (regr.)", "warn", "fade",
                "disarm", "clamps");
  for (const auto& d : r.devices) {
    const std::string echo = d.flow.models_used ? Printf("%llu->%llu (%llu)", U(d.first_echo_seq),
                                                         U(d.last_echo_seq), U(d.flow.echo_regressions))
                                                : "none";
    out += TableRow(std::to_string(d.device_id), d.session, d.flow, echo);
  }
  const LoadTotals& t = r.total;
  out += TableRow("total", Printf("%zu/%zu w/ models", t.devices_with_models, t.devices), t.flow,
                  Printf("regressions %llu", U(t.flow.echo_regressions)));
  out += "(times in ms)\n";
  out += Printf("servo thread: %llu ticks, lateness %s, work per tick %s, re-anchors %llu\n", U(r.servo.ticks),
                common::FormatPercentiles(r.servo.lateness_s, kMs, "ms").c_str(),
                common::FormatPercentiles(r.servo.work_s, kMs, "ms").c_str(), U(r.servo.reanchors));
  out += Printf(
      "models dropped: %llu for other devices, %llu for our devices but another session, %llu from a "
      "server other than the one each device follows\n",
      U(r.models_for_unknown_devices), U(r.models_for_other_sessions), U(r.models_from_other_servers));
  if (!r.server.empty()) {
    out += Printf("%-14s %9s %10s %14s %13s %9s %6s\n", "server:session", "ticks", "late_ticks", "device_clocked",
                  "max_late_ms", "streaming", "owner");
    for (const auto& s : r.server) {
      if (!s.error.empty()) {
        out += Printf("%-14s %s\n", s.session_id.c_str(), s.error.c_str());
        continue;
      }
      out += Printf("%-14s %9llu %10llu %14llu %13.3f %9s %6u\n", s.session_id.c_str(), U(s.ticks), U(s.late_ticks),
                    U(s.device_clocked_ticks), s.max_tick_lateness_s * kMs, s.device_streaming ? "yes" : "no",
                    s.owning_device_id);
    }
  }
  return out;
}

std::string FormatLoadJson(const LoadReport& r) {
  Json j;
  j["rate_hz"] = r.rate_hz;
  j["elapsed_s"] = r.elapsed_s;
  j["servo_thread"] = {{"ticks", r.servo.ticks},
                       {"reanchors", r.servo.reanchors},
                       {"lateness_ms", PercentilesMs(r.servo.lateness_s)},
                       {"work_ms", PercentilesMs(r.servo.work_s)}};
  j["models_for_unknown_devices"] = r.models_for_unknown_devices;
  j["models_for_other_sessions"] = r.models_for_other_sessions;
  j["models_from_other_servers"] = r.models_from_other_servers;
  j["total"] = TotalJson(r.total);
  j["per_device"] = Json::array();
  for (const auto& d : r.devices) j["per_device"].push_back(DeviceJson(d));
  if (!r.server.empty()) {
    j["server_sessions"] = Json::array();
    for (const auto& s : r.server) j["server_sessions"].push_back(ServerJson(s));
  }
  if (!r.intervals.empty()) {
    j["intervals"] = Json::array();
    for (const auto& i : r.intervals) {
      j["intervals"].push_back({{"end_s", i.end_s},
                                {"round_trip_ms", PercentilesMs(i.round_trip_s)},
                                {"model_age_ms", PercentilesMs(i.model_age_s)}});
    }
    j["intervals_dropped"] = r.intervals_dropped;
  }
  // Invalid UTF-8 in a session id (never from our own ids) is replaced, not thrown.
  return j.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

std::string FormatLoadIntervalsCsv(const LoadReport& r) {
  std::string out =
      "end_s,round_trips,round_trip_p50_ms,round_trip_p99_ms,round_trip_max_ms,model_ages,model_age_p50_ms,"
      "model_age_p99_ms,model_age_max_ms\n";
  for (const auto& i : r.intervals) {
    const common::Percentiles &rtt = i.round_trip_s, &age = i.model_age_s;
    out += Printf("%.3f,%zu,%.4f,%.4f,%.4f,%zu,%.4f,%.4f,%.4f\n", i.end_s, rtt.count, rtt.p50 * kMs, rtt.p99 * kMs,
                  rtt.max * kMs, age.count, age.p50 * kMs, age.p99 * kMs, age.max * kMs);
  }
  return out;
}

std::string FormatLoadCsv(const LoadReport& r) {
  std::string out =
      "device_id,session,poses_sent,pose_rate_hz,models_received,models_used,first_echo_seq,last_echo_seq,"
      "echo_regressions,round_trip_p50_ms,round_trip_p99_ms,round_trip_max_ms,model_age_p50_ms,model_age_p99_ms,"
      "model_age_max_ms,watchdog_warnings,watchdog_fades,watchdog_disarms,force_clamps,final_watchdog\n";
  for (const auto& d : r.devices) {
    out += std::to_string(d.device_id) + "," + d.session + "," +
           CsvFlowAndEcho(d.flow, d.first_echo_seq, d.last_echo_seq, ToString(d.final_watchdog));
  }
  out += "total,," + CsvFlowAndEcho(r.total.flow, 0, 0, "");
  return out;
}

bool WriteTextFile(const std::string& path, const std::string& text) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) return false;
  const bool written = std::fwrite(text.data(), 1, text.size(), f) == text.size();
  return std::fclose(f) == 0 && written;
}

}  // namespace hapsim::bridge
