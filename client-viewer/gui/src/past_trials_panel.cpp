#include <imgui.h>

#include <algorithm>
#include <cinttypes>
#include <utility>

#include "hapsim/common/local_time.h"
#include "hapsim/gui/viewer_panels.h"

namespace hapsim::gui {

namespace {

// The open replay: where it is, whether it is still the trial as it was, and its controls.
std::string DrawReplay(const hapsim::v1::ReplayInfo& r, const std::string& watched, PastTrials* past,
                       PastTrialsPanel* panel) {
  std::string watch;
  const std::string& id = r.session().session_id();
  ImGui::Text("%s: %s", id.c_str(), r.recording_id().c_str());
  const bool diverged = r.checkpoints_diverged() > 0;
  ImGui::TextColored(diverged ? ImVec4(1.0f, 0.4f, 0.3f, 1) : ImVec4(0.5f, 0.9f, 0.5f, 1),
                     "checkpoints %" PRIu64 "/%" PRIu64 " matched, %" PRIu64 " diverged%s", r.checkpoints_matched(),
                     r.checkpoints(), r.checkpoints_diverged(), r.ended() ? ", ended" : "");
  if (ImGui::SmallButton(r.session().paused() ? "Play" : "Pause")) past->SetPaused(!r.session().paused());
  ImGui::SameLine();
  ImGui::BeginDisabled(!r.session().paused());
  if (ImGui::SmallButton("Step 1 tick")) past->Step(1);
  ImGui::SameLine();
  if (ImGui::SmallButton("Step 100")) past->Step(100);
  ImGui::EndDisabled();
  ImGui::SameLine();
  if (id != watched && ImGui::SmallButton("Watch")) watch = id;
  if (id != watched) ImGui::SameLine();
  if (ImGui::SmallButton("Close")) past->Close();
  const float length_s = static_cast<float>(r.trial_length_s());
  if (!panel->dragging) panel->seek_s = static_cast<float>(r.trial_s());
  ImGui::SetNextItemWidth(-1.0f);
  ImGui::SliderFloat("##seek", &panel->seek_s, 0.0f, std::max(length_s, 0.001f), "%.2f s");
  panel->dragging = ImGui::IsItemActive();
  if (ImGui::IsItemDeactivatedAfterEdit()) past->Seek(panel->seek_s);
  ImGui::TextDisabled("%.2f of %.2f s at %.1fx; the last seek re-ran %" PRIu64 " ticks (%" PRIu64 " states kept)",
                      r.trial_s(), r.trial_length_s(), r.speed(), r.rerun_ticks(), r.kept_states());
  return watch;
}

}  // namespace

std::string DrawPastTrials(const PastTrials::View& view, const std::string& watched, PastTrials* past,
                           PastTrialsPanel* panel) {
  std::string watch;
  if (ImGui::SmallButton("Refresh")) past->Refresh();
  ImGui::SameLine();
  if (!view.listed)
    ImGui::TextDisabled(view.busy ? "listing..." : "not listed");
  else
    ImGui::Text("%zu recorded trials%s", view.trials.size(), view.busy ? " ..." : "");
  if (view.replay) watch = DrawReplay(*view.replay, watched, past, panel);
  constexpr ImGuiTableFlags kFlags = ImGuiTableFlags_RowBg | ImGuiTableFlags_BordersInnerV | ImGuiTableFlags_ScrollY;
  const float rows_px =
      ImGui::GetTextLineHeightWithSpacing() * static_cast<float>(std::min<std::size_t>(view.trials.size() + 1, 8));
  if (!view.trials.empty() && ImGui::BeginTable("past_trials", 6, kFlags, ImVec2(0.0f, rows_px + 8.0f))) {
    ImGui::TableSetupScrollFreeze(0, 1);
    // Fixed widths (in characters): the first frame, a picture's only one, is laid out right too.
    const float char_px = ImGui::CalcTextSize("0").x;
    for (const auto& [name, chars] :
         {std::pair{"session", 8}, {"trainee", 10}, {"trial", 11}, {"started", 12}, {"ticks", 7}}) {
      ImGui::TableSetupColumn(name, ImGuiTableColumnFlags_WidthFixed, char_px * static_cast<float>(chars));
    }
    ImGui::TableSetupColumn("", ImGuiTableColumnFlags_WidthStretch);
    ImGui::TableHeadersRow();
    for (const auto& r : view.trials) {
      ImGui::PushID(r.id().c_str());
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(r.session_id().c_str());
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(r.trainee().c_str());
      ImGui::TableNextColumn();
      ImGui::Text("%" PRIu64 "%s", r.trial(), r.status() == "open" ? " (running)" : "");
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(common::LocalTimeText(r.started_unix_ms(), "%m-%d %H:%M").c_str());
      ImGui::TableNextColumn();
      ImGui::Text("%" PRIu64, r.ticks());
      ImGui::TableNextColumn();
      if (ImGui::SmallButton("Open")) past->Open(r.id());
      ImGui::PopID();
    }
    ImGui::EndTable();
  }
  if (!view.last_result.empty()) ImGui::TextWrapped("%s", view.last_result.c_str());
  return watch;
}

}  // namespace hapsim::gui
