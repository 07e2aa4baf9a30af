#include "hapsim/gui/viewer_panels.h"

#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include "hapsim/gui/plot_widgets.h"

namespace hapsim::gui {

SessionControls::SessionControls(const viewer::Connection& connection) {
  try {
    client_ = std::make_unique<viewer::SessionClient>(connection, 5.0);
  } catch (const std::exception& e) {
    init_error_ = e.what();
  }
}

void SessionControls::Send(viewer::SessionClient::Control control, const std::string& session_id) {
  if (!client_) {
    last_ = init_error_;
    return;
  }
  if (busy()) return;
  static constexpr const char* kVerb[] = {"pause", "resume", "reset"};
  const std::string verb = kVerb[static_cast<int>(control)];
  pending_ = std::async(std::launch::async, [client = client_.get(), control, session_id, verb] {
    v1::SessionInfo info;
    const grpc::Status status = client->Apply(control, session_id, &info);
    return status.ok() ? verb + " " + session_id + ": ok" : verb + " " + session_id + ": " + viewer::DescribeStatus(status);
  });
}

bool SessionControls::busy() {
  if (!pending_.valid()) return false;
  if (pending_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return true;
  last_ = pending_.get();
  return false;
}

const std::string& SessionControls::last_result() {
  busy();  // collects a finished answer
  return last_;
}

void StreamRate::Update(const SceneView& scene, double now_s, double dt_s) {
  if (scene.version != seen_version) {
    seen_version = scene.version;
    since_frame_s = 0.0;
  } else {
    since_frame_s += dt_s;
  }
  if (last_time_s < 0.0) {
    last_time_s = now_s;
    last_frames = scene.frames;
  } else if (now_s - last_time_s >= 1.0) {
    fps = static_cast<double>(scene.frames - std::min(last_frames, scene.frames)) / (now_s - last_time_s);
    last_time_s = now_s;
    last_frames = scene.frames;
  }
}

namespace {

ImVec4 ContactColour(const std::string& state) {
  if (state == "punctured") return ImVec4(1.0f, 0.35f, 0.35f, 1.0f);
  if (state == "cutting") return ImVec4(1.0f, 0.6f, 0.2f, 1.0f);
  if (state == "contact") return ImVec4(1.0f, 0.9f, 0.3f, 1.0f);
  return ImVec4(0.6f, 0.9f, 0.6f, 1.0f);
}

}  // namespace

namespace {

void DrawStreamStatus(const SceneView& scene, const std::string& session_id, const std::string& server,
                      const StreamRate& rate) {
  ImGui::Text("session %s  on %s", session_id.c_str(), server.c_str());
  const bool live = scene.connection == "live";
  ImGui::TextColored(live ? ImVec4(0.5f, 0.9f, 0.5f, 1) : ImVec4(1.0f, 0.6f, 0.3f, 1), "%s", scene.connection.c_str());
  ImGui::Text("frames %llu  %.0f/s  last %.0f ms ago", static_cast<unsigned long long>(scene.frames), rate.fps,
              1e3 * rate.since_frame_s);
  ImGui::Text("sim time %.2f s%s", scene.sim_time_s, scene.paused ? "  [paused]" : "");
}

void DrawToolState(const SceneView& scene) {
  ImGui::Text("contact");
  ImGui::SameLine(90);
  ImGui::TextColored(ContactColour(scene.tool.contact_state), "%s",
                     scene.tool.contact_state.empty() ? "-" : scene.tool.contact_state.c_str());
  const std::string layer = scene.LayerName(scene.current_layer);
  ImGui::Text("layer");
  ImGui::SameLine(90);
  ImGui::Text("%s", layer.empty() ? "-" : layer.c_str());
  ImGui::Text("depth");
  ImGui::SameLine(90);
  ImGui::Text("%.2f mm", 1e3 * scene.tip_depth_m);
  ImGui::Text("|force|");
  ImGui::SameLine(90);
  ImGui::Text("%.3f N", scene.tool.force_N.norm());
}

void DrawViewControls(ViewState* view) {
  if (ImGui::Button("Reset view")) view->reset_view = true;
  ImGui::SameLine();
  ImGui::Checkbox("Follow tool", &view->follow_tool);
  ImGui::Checkbox("See-through layers", &view->render.see_through_layers);
  ImGui::SameLine();
  ImGui::Checkbox("Force", &view->render.show_force);
  // Fine meshes are drawn simplified (software rendering pays per triangle).
  bool simplify = view->render.max_triangles > 0;
  if (ImGui::Checkbox("Simplify fine meshes", &simplify))
    view->render.max_triangles = simplify ? RenderOptions{}.max_triangles : 0;
  if (view->drawn_triangles < view->mesh_triangles) {
    ImGui::SameLine();
    ImGui::TextDisabled("%zu of %zu triangles", view->drawn_triangles, view->mesh_triangles);
  }
}

void DrawSessionButtons(bool paused, const std::string& session_id, SessionControls* controls) {
  using Control = viewer::SessionClient::Control;
  const bool busy = controls->busy();
  if (busy) ImGui::BeginDisabled();
  if (ImGui::Button(paused ? "Resume" : "Pause"))
    controls->Send(paused ? Control::kResume : Control::kPause, session_id);
  ImGui::SameLine();
  if (ImGui::Button("Reset session")) controls->Send(Control::kReset, session_id);
  if (busy) ImGui::EndDisabled();
  const std::string& result = controls->last_result();
  if (!result.empty()) ImGui::TextWrapped("%s", result.c_str());
}

// The first sample at or after t_s (the history's times never decrease: it
// starts again when time goes back).
std::size_t FirstSampleFrom(const ForceHistory& history, double t_s) {
  std::size_t lo = 0, hi = history.size();
  while (lo < hi) {
    const std::size_t mid = lo + (hi - lo) / 2;
    if (history[mid].t_s < t_s)
      lo = mid + 1;
    else
      hi = mid;
  }
  return lo;
}

}  // namespace

void DrawSessionPanel(const SceneView& scene, const std::string& session_id, const std::string& server,
                      const StreamRate& rate, ViewState* view, SessionControls* controls) {
  DrawStreamStatus(scene, session_id, server, rate);
  ImGui::Separator();
  DrawToolState(scene);
  ImGui::Separator();
  DrawViewControls(view);
  if (controls && !session_id.empty()) DrawSessionButtons(scene.paused, session_id, controls);
}

double ForceAxisTop_N(double peak_N) { return 1.1 * std::max(peak_N, kMinForceAxis_N); }

// Both plots read the history where it is: the one of force vs time its
// last kWindow_s, the one of force vs depth all of it.
void DrawForcePlots(const SceneView& scene, float width_px, float plot_height_px) {
  constexpr double kWindow_s = 10.0;
  const ForceHistory& h = scene.history;
  const double t_end = h.empty() ? 0.0 : h.back().t_s;
  double f_max = 0.0, d_max = 2.0;
  for (std::size_t i = 0; i < h.size(); ++i) {
    d_max = std::max(d_max, 1e3 * h[i].depth_m);
    f_max = std::max(f_max, h[i].force_N);
  }
  const double f_top = ForceAxisTop_N(f_max);
  const std::size_t first = FirstSampleFrom(h, t_end - kWindow_s);
  const PlotSeries force_time{h.size() - first, [&](std::size_t i) { return h[first + i].t_s; },
                              [&](std::size_t i) { return h[first + i].force_N; }};
  PlotAxes time_axes{"force on the tool vs time", "t [s]", "|F| [N]", std::max(0.0, t_end - kWindow_s),
                     std::max(kWindow_s, t_end),  0.0,     f_top};
  PlotLine("force_time", time_axes, force_time, width_px, plot_height_px, IM_COL32(255, 190, 50, 255));
  const PlotSeries force_depth{h.size(), [&](std::size_t i) { return 1e3 * h[i].depth_m; },
                               [&](std::size_t i) { return h[i].force_N; }};
  PlotAxes depth_axes{
      "force vs tip depth (since reset)", "depth below the surface [mm]", "|F| [N]", 0.0, 1.05 * d_max, 0.0, f_top};
  PlotLine("force_depth", depth_axes, force_depth, width_px, plot_height_px, IM_COL32(90, 200, 255, 255));
}

void DrawEventList(const SceneView& scene) {
  int shown = 0;
  for (auto e = scene.events.rbegin(); e != scene.events.rend() && shown < 40; ++e, ++shown) {
    const ImVec4 colour = viewer::MarksTissue(e->kind) ? ImVec4(1.0f, 0.5f, 0.4f, 1) : ImVec4(0.75f, 0.75f, 0.75f, 1);
    const char* kind = viewer::ToString(e->kind);
    if (e->kind == viewer::EventKind::kCutEnd)
      ImGui::TextColored(colour, "%8.3f s  %s  %.1f mm", e->t_s, kind, 1e3 * e->value);
    else if (e->has_where)
      ImGui::TextColored(colour, "%8.3f s  %s  %s  z %.2f mm", e->t_s, kind, e->layer.c_str(), 1e3 * e->where_m.z());
    else
      ImGui::TextColored(colour, "%8.3f s  %s  %s", e->t_s, kind, e->layer.c_str());
  }
  if (shown == 0) ImGui::TextDisabled("no events yet");
}

TileGrid ClassTileGrid(float avail_px, float spacing_px) {
  TileGrid grid;
  grid.columns = std::max(1, static_cast<int>((avail_px + spacing_px) / (TileGrid::kMinTileWidth_px + spacing_px)));
  grid.tile_width_px = std::max(TileGrid::kMinTileWidth_px,
                                (avail_px - static_cast<float>(grid.columns - 1) * spacing_px) / grid.columns);
  return grid;
}

namespace {

// One session's tile; true when its View button was clicked.
bool DrawSessionTile(const SessionTile& tile, bool selected, float tile_w, SessionControls* controls) {
  constexpr float kTileHeight_px = 150.0f;
  const auto& s = tile.status;
  ImGui::PushID(s.session_id().c_str());
  ImGui::PushStyleColor(ImGuiCol_ChildBg, selected ? ImVec4(0.18f, 0.26f, 0.38f, 1) : ImVec4(0.14f, 0.15f, 0.18f, 1));
  ImGui::BeginChild("tile", ImVec2(tile_w, kTileHeight_px), true, ImGuiWindowFlags_NoScrollbar);
  ImGui::TextColored(s.device_streaming() ? ImVec4(0.4f, 0.9f, 0.4f, 1) : ImVec4(0.9f, 0.3f, 0.3f, 1), "%s",
                     s.device_streaming() ? "DEV" : "dev");
  ImGui::SameLine();
  ImGui::Text("%s  %s  %s%s", s.session_id().c_str(), s.trainee().c_str(), s.scene().c_str(),
              s.paused() ? " [paused]" : "");
  ImGui::TextColored(ContactColour(s.contact_state()), "%-9s", s.contact_state().c_str());
  ImGui::SameLine();
  ImGui::Text("%5.2f mm %s", 1e3 * s.tip_depth_m(), s.layer_name().empty() ? "-" : s.layer_name().c_str());
  ImGui::Text("|F| %.3f N  peak %.2f N", s.force_n(), s.peak_tool_force_n());
  std::vector<float> history(tile.force_history_N.begin(), tile.force_history_N.end());
  float top = 0.5f;
  for (const float f : history) top = std::max(top, f);
  ImGui::PlotLines("##force", history.data(), static_cast<int>(history.size()), 0, nullptr, 0.0f, 1.1f * top,
                   ImVec2(tile_w - 16.0f, 34.0f));
  ImGui::Text("late %llu  events %llu", static_cast<unsigned long long>(s.late_ticks()),
              static_cast<unsigned long long>(s.events_total()));
  if (!tile.recent_events.empty()) {
    ImGui::SameLine();
    ImGui::TextDisabled("%s", tile.recent_events.back().c_str());
  }
  const bool clicked = ImGui::SmallButton("View");
  if (controls) {
    using Control = viewer::SessionClient::Control;
    ImGui::SameLine();
    if (ImGui::SmallButton(s.paused() ? "Resume" : "Pause"))
      controls->Send(s.paused() ? Control::kResume : Control::kPause, s.session_id());
    ImGui::SameLine();
    if (ImGui::SmallButton("Reset")) controls->Send(Control::kReset, s.session_id());
  }
  ImGui::EndChild();
  ImGui::PopStyleColor();
  ImGui::PopID();
  return clicked;
}

}  // namespace

std::string DrawClassConsole(const ClassView& view, const std::string& watched, SessionControls* controls) {
  std::string clicked;
  ImGui::Text("class %s  update %llu", view.class_name.empty() ? "(all sessions)" : view.class_name.c_str(),
              static_cast<unsigned long long>(view.updates));
  const bool live = view.connection == "live";
  ImGui::TextColored(live ? ImVec4(0.5f, 0.9f, 0.5f, 1) : ImVec4(1.0f, 0.6f, 0.3f, 1), "%s", view.connection.c_str());
  const TileGrid grid = ClassTileGrid(ImGui::GetContentRegionAvail().x, ImGui::GetStyle().ItemSpacing.x);
  int i = 0;
  for (const auto& tile : view.sessions) {
    if (i % grid.columns != 0) ImGui::SameLine();
    ++i;
    if (DrawSessionTile(tile, tile.status.session_id() == watched, grid.tile_width_px, controls))
      clicked = tile.status.session_id();
  }
  for (const auto& m : view.missing) ImGui::TextDisabled("%s (not running)", m.c_str());
  if (controls && !controls->last_result().empty()) ImGui::TextWrapped("%s", controls->last_result().c_str());
  return clicked;
}

}  // namespace hapsim::gui
