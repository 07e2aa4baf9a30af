#include "hapsim/classroom/trial_book.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "hapsim/common/clock.h"

namespace hapsim::service {

TrialRecord TrialBook::Describe(const Session& session, const SessionTrials& trials, const TrialStats& stats,
                                const char* end) {
  TrialRecord r;
  r.session_id = session.id();
  r.trainee = session.config().owner;
  r.scene = session.config().scene;
  r.layer_names = session.layer_names();
  r.targets = trials.targets();
  r.stats = stats;
  r.end = end;
  return r;
}

void TrialBook::SetSink(std::function<void(const TrialRecord&)> sink, double running_every_s) {
  std::lock_guard lock(mutex_);
  sink_ = std::move(sink);
  sink_running_every_ns_ = static_cast<std::int64_t>(running_every_s * 1e9);
}

void TrialBook::Preload(std::vector<TrialRecord> ended) {
  std::lock_guard lock(mutex_);
  for (auto& r : ended) ended_.push_back(std::move(r));
  while (ended_.size() > kMaxTrials) ended_.pop_front();
}

void TrialBook::AddEndedLocked(TrialRecord record) {
  if (sink_) sink_(record);
  ended_.push_back(std::move(record));
  while (ended_.size() > kMaxTrials) ended_.pop_front();
}

void TrialBook::Observe(const SessionTable& sessions) {
  std::lock_guard lock(mutex_);
  // The pump runs every few milliseconds: present sessions are marked with
  // the pass number rather than collected into a set (no allocation per pass).
  const std::uint64_t pass = ++observe_passes_;
  for (const auto& [id, session] : sessions) {
    SessionTrials* trials = TrialsOf(*session);
    if (!trials) continue;  // a session made without trials
    auto [it, fresh] = running_.try_emplace(session.get());
    if (fresh || it->second.session != session) {
      it->second = Running{session, Describe(*session, *trials, TrialStats{}, "running")};
    }
    it->second.seen_pass = pass;
    TrialStats stats;
    if (trials->TakeFinished(&stats)) AddEndedLocked(Describe(*session, *trials, stats, "reset"));
    if (trials->TakeRunning(&stats)) {
      it->second.record.stats = stats;
      const std::int64_t now_ns = common::SteadyNowNs();
      if (sink_ && now_ns - it->second.sunk_ns >= sink_running_every_ns_) {
        it->second.sunk_ns = now_ns;
        sink_(it->second.record);
      }
    }
  }
  for (auto it = running_.begin(); it != running_.end();) {
    if (it->second.seen_pass == pass) {
      ++it;
      continue;
    }
    TrialRecord last = it->second.record;  // the session closed: its running trial ended
    last.end = "closed";
    if (last.stats.ticks > 0) AddEndedLocked(std::move(last));
    it = running_.erase(it);
  }
}

std::vector<TrialRecord> TrialBook::Trials(const std::function<bool(const std::string&)>& include) const {
  std::lock_guard lock(mutex_);
  std::vector<TrialRecord> out;
  for (const auto& r : ended_) {
    if (!include || include(r.session_id)) out.push_back(r);
  }
  for (const auto& [key, running] : running_) {
    if (!include || include(running.record.session_id)) out.push_back(running.record);
  }
  std::stable_sort(out.begin(), out.end(), [](const TrialRecord& a, const TrialRecord& b) {
    return a.session_id != b.session_id ? a.session_id < b.session_id : a.stats.trial < b.stats.trial;
  });
  return out;
}

namespace {

// Fixed-point text with `decimals` digits; "" for NaN (no value).
std::string Number(double v, int decimals = 4) {
  if (!std::isfinite(v)) return "";
  char buffer[48];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, v);
  return buffer;
}

// CSV field: quoted when it holds a comma, quote or newline.
std::string Field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (const char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

}  // namespace

std::string FormatTrialsCsv(const std::vector<TrialRecord>& trials,
                            const std::function<std::string(const std::string&)>& score_of) {
  std::string csv =
      "session,trainee,scene,trial,end,duration_s,time_to_contact_s,peak_force_N,max_depth_mm,target_depth_mm,"
      "depth_error_mm,layers_pierced,punctures,peak_force_by_layer_N,incisions,incision_length_mm,"
      "line_deviation_max_mm,line_deviation_mean_mm,score\n";
  for (const TrialRecord& r : trials) {
    const TrialStats& s = r.stats;
    std::string pierced, by_layer;
    for (std::size_t l = 0; l < r.layer_names.size() && l < TrialStats::kMaxLayers; ++l) {
      if (s.layers_pierced_mask & (1u << l)) pierced += (pierced.empty() ? "" : "+") + r.layer_names[l];
      if (s.peak_force_in_layer_N[l] > 0.0) {
        by_layer += (by_layer.empty() ? "" : ";") + r.layer_names[l] + "=" + Number(s.peak_force_in_layer_N[l]);
      }
    }
    const bool has_depth = !std::isnan(r.targets.depth_m);
    const bool touched = !std::isnan(s.first_contact_sim_s);  // no contact: no depth error to speak of
    const bool has_line = r.targets.has_line();
    csv += Field(r.session_id) + "," + Field(r.trainee) + "," + Field(r.scene) + "," + std::to_string(s.trial) +
           "," + r.end + "," + Number(s.duration_s(), 3) + "," +
           Number(s.first_contact_sim_s - s.start_sim_s, 3) + "," + Number(s.peak_force_N) + "," +
           Number(s.max_tip_depth_m * 1e3, 3) + "," + (has_depth ? Number(r.targets.depth_m * 1e3, 3) : "") +
           "," + (has_depth && touched ? Number((s.max_tip_depth_m - r.targets.depth_m) * 1e3, 3) : "") + "," +
           Field(pierced) + "," + std::to_string(s.punctures) + "," + Field(by_layer) + "," + std::to_string(s.cuts) +
           "," + Number(s.incision_length_m * 1e3, 3) + "," +
           (has_line && s.cutting_ticks ? Number(s.line_deviation_max_m * 1e3, 3) : "") + "," +
           (has_line && s.cutting_ticks ? Number(s.line_deviation_mean_m() * 1e3, 3) : "") + "," +
           (score_of ? score_of(r.session_id) : "") + "\n";
  }
  return csv;
}

}  // namespace hapsim::service
