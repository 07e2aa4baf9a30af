#include "hapsim/load/load_report.h"

namespace hapsim::bridge {

namespace {

void AddCounts(const LoadFlow& f, LoadFlow* sum) {
  sum->poses_sent += f.poses_sent;
  sum->pose_write_failures += f.pose_write_failures;
  sum->pose_rate_hz += f.pose_rate_hz;
  sum->models_received += f.models_received;
  sum->models_used += f.models_used;
  sum->echo_regressions += f.echo_regressions;
  sum->models_unused += f.models_unused;
  sum->safety.non_finite += f.safety.non_finite;
  sum->safety.clamped += f.safety.clamped;
  sum->safety.rate_limited += f.safety.rate_limited;
  sum->safety.warnings += f.safety.warnings;
  sum->safety.fades += f.safety.fades;
  sum->safety.disarms += f.safety.disarms;
  sum->safety.delay_warnings += f.safety.delay_warnings;
}

}  // namespace

LoadTotals SumDevices(const std::vector<LoadDeviceReport>& devices) {
  LoadTotals t;
  t.devices = devices.size();
  for (const auto& d : devices) {
    if (d.flow.models_used > 0) ++t.devices_with_models;
    if (d.flow.safety.disarms > 0) ++t.devices_disarmed;
    AddCounts(d.flow, &t.flow);
  }
  return t;
}

}  // namespace hapsim::bridge
