#include "hapsim/api/class_status.h"

#include <algorithm>

#include "hapsim/api/class_status_events.h"

namespace hapsim::service {

void ClassStatusBuilder::Describe(const std::shared_ptr<Session>& session, hapsim::v1::SessionStatus* out,
                                  std::vector<PendingEvents>* pending) {
  const auto& c = session->counters();
  out->set_session_id(session->id());
  out->set_trainee(session->config().owner);
  out->set_scene(session->config().scene);
  out->set_sim_time_s(c.tick.sim_time_s.load());
  out->set_ticks(c.tick.ticks.load());
  out->set_late_ticks(c.tick.late_ticks.load());
  out->set_max_tick_lateness_s(static_cast<double>(c.tick.max_lateness_ns.load()) * 1e-9);
  out->set_device_streaming(c.tick.device_streaming.load());
  out->set_paused(session->paused());
  out->set_peak_tool_force_n(c.tick.peak_tool_force_N.load());
  out->set_viewers(c.viewers.connected.load());
  if (const auto score = scores_->SummaryOf(session->id())) {
    out->set_experts(score->experts);
    out->set_score(score->score);
  }
  auto snap = hub_->LatestSnapshot(*session);
  if (!snap) {
    out->set_current_layer(-1);
    out->set_contact_state("free");
    return;
  }
  out->set_tip_depth_m(snap->tip_depth_m);
  out->set_current_layer(snap->current_layer);
  if (snap->layer_names && snap->current_layer >= 0 &&
      static_cast<std::size_t>(snap->current_layer) < snap->layer_names->size()) {
    out->set_layer_name((*snap->layer_names)[static_cast<std::size_t>(snap->current_layer)]);
  }
  out->set_force_n(snap->tool_force_W_N.norm());
  out->set_contact_state(core::ToString(snap->contact));
  out->set_events_total(snap->events_total);
  Cursor& cursor = cursors_[session->id()];
  if (cursor.session != session) cursor = Cursor{session, FirstEventToSend(snap->events_total)};
  pending->push_back({out, snap.get(), &cursor.events_sent});
  held_snapshots_.push_back(std::move(snap));
}

void ClassStatusBuilder::Fill(const std::vector<std::string>* session_ids, hapsim::v1::ClassStatus* out) {
  out->set_seq(seq_++);
  const auto table = registry_->Table();
  std::vector<PendingEvents> pending;
  held_snapshots_.clear();
  if (!session_ids) {
    for (const auto& [id, session] : *table) Describe(session, out->add_sessions(), &pending);
  } else {
    std::vector<std::string> ids = *session_ids;
    std::sort(ids.begin(), ids.end());
    for (const auto& id : ids) {
      const auto found = table->find(id);
      if (found == table->end()) {
        out->add_missing_sessions(id);
        cursors_.erase(id);
      } else {
        Describe(found->second, out->add_sessions(), &pending);
      }
    }
  }
  AddEventsWithinBudget(pending, ClassStatusBudgetBytes(static_cast<std::size_t>(out->sessions_size())), out);
  held_snapshots_.clear();
}

}  // namespace hapsim::service
