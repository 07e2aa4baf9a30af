#include "hapsim/load/load_plan.h"

#include <algorithm>
#include <set>
#include <sstream>
#include <stdexcept>

#include "hapsim/common/session_id.h"

namespace hapsim::bridge {

std::vector<std::string> SplitCommaList(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    if (!item.empty()) items.push_back(item);
  }
  return items;
}

std::vector<LoadDevicePlan> PlanDevices(const LoadPlanOptions& o) {
  std::vector<std::string> sessions = o.sessions;
  if (sessions.empty()) {
    if (o.devices < 1 || o.devices > 1024) throw std::invalid_argument("--devices must be in [1, 1024]");
    for (int i = 0; i < o.devices; ++i) sessions.push_back(o.session_prefix + std::to_string(i));
  }
  if (!(o.phase_spread_s >= 0.0)) throw std::invalid_argument("--phase-spread-s must be >= 0");
  if (!(o.clock_phase_spread >= 0.0 && o.clock_phase_spread <= 1.0)) {
    throw std::invalid_argument("--clock-phase-spread must be within [0, 1]");
  }
  if (!(o.clock_rate_ppm >= 0.0 && o.clock_rate_ppm <= 10000.0)) {
    throw std::invalid_argument("--clock-rate-ppm must be within [0, 10000]");
  }
  std::set<std::string> seen;
  for (const auto& s : sessions) {
    if (!common::IsValidSessionId(s)) throw std::invalid_argument("session id '" + s + "' is not [A-Za-z0-9_-]{1,63}");
    if (!seen.insert(s).second) throw std::invalid_argument("session '" + s + "' is listed twice (one device per session)");
  }
  const std::size_t n = sessions.size();
  std::vector<LoadDevicePlan> plan(n);
  for (std::size_t i = 0; i < n; ++i) {
    plan[i].device_id = o.first_device_id + static_cast<std::uint32_t>(i);
    plan[i].session = sessions[i];
    plan[i].script = o.script;
    plan[i].script.seed = o.script.seed + static_cast<std::uint32_t>(i);
    plan[i].phase_s = o.phase_spread_s * static_cast<double>(i) / static_cast<double>(n);
    const double fraction = static_cast<double>(i) / static_cast<double>(n);  // [0, 1)
    plan[i].clock_phase_s = o.clock_phase_spread * fraction * o.period_s;
    // -ppm for device 0 up to +ppm for the last: every pair drifts apart at a different rate.
    plan[i].clock_rate_ppm =
        n > 1 ? o.clock_rate_ppm * (2.0 * static_cast<double>(i) / static_cast<double>(n - 1) - 1.0) : 0.0;
  }
  return plan;
}

bool HasOwnClocks(const std::vector<LoadDevicePlan>& plan) {
  return std::any_of(plan.begin(), plan.end(),
                     [](const LoadDevicePlan& p) { return p.clock_phase_s != 0.0 || p.clock_rate_ppm != 0.0; });
}

}  // namespace hapsim::bridge
