// hapsim-load's report as a table for people, JSON and CSV for scripts.
// Times are in milliseconds in every format (keys and columns say so).
#pragma once
#include <string>

#include "hapsim/load/load_report.h"

namespace hapsim::bridge {

std::string FormatLoadTable(const LoadReport& report);
// {rate_hz, elapsed_s, servo_thread{...}, total{...}, per_device[...], server_sessions[...], intervals[...]}
std::string FormatLoadJson(const LoadReport& report);
// One row per device, then a row with device_id "total".
std::string FormatLoadCsv(const LoadReport& report);
// One row per --interval-s interval: its end [s], then round trip and model
// age (count, p50, p99, max in ms), pooled over the devices.
std::string FormatLoadIntervalsCsv(const LoadReport& report);
bool WriteTextFile(const std::string& path, const std::string& text);

}  // namespace hapsim::bridge
