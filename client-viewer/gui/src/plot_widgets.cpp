#include "hapsim/gui/plot_widgets.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace hapsim::gui {

double NiceTickStep(double range, int ticks) {
  if (!(range > 0.0) || ticks < 1) return 1.0;
  const double raw = range / ticks;
  const double decade = std::pow(10.0, std::floor(std::log10(raw)));
  const double m = raw / decade;
  return decade * (m < 1.5 ? 1.0 : m < 3.5 ? 2.0 : m < 7.5 ? 5.0 : 10.0);
}

namespace {

// Maps plot coordinates into the frame [lo, hi] of the plot area (screen y down).
struct PlotFrame {
  ImVec2 lo, hi;
  double x_min, y_min, x_range, y_range;
  ImVec2 ToScreen(double vx, double vy) const {
    return ImVec2(lo.x + static_cast<float>((vx - x_min) / x_range) * (hi.x - lo.x),
                  hi.y - static_cast<float>((vy - y_min) / y_range) * (hi.y - lo.y));
  }
};

void DrawPlotAxes(ImDrawList* draw, const PlotAxes& axes, const PlotFrame& frame, const ImVec2& origin) {
  char text[32];
  const ImU32 grid = IM_COL32(70, 74, 82, 255), label = IM_COL32(200, 200, 200, 255);
  const ImVec2 lo = frame.lo, hi = frame.hi;
  const double xr = frame.x_range, yr = frame.y_range;
  const double xs = NiceTickStep(xr, 5), ys = NiceTickStep(yr, 4);
  for (double v = std::ceil(axes.x_min / xs) * xs; v <= axes.x_max + 1e-9 * xr; v += xs) {
    const ImVec2 p = frame.ToScreen(v, axes.y_min);
    draw->AddLine(ImVec2(p.x, lo.y), ImVec2(p.x, hi.y), grid);
    std::snprintf(text, sizeof text, "%g", std::abs(v) < 1e-9 * xr ? 0.0 : v);
    draw->AddText(ImVec2(p.x - ImGui::CalcTextSize(text).x / 2, hi.y + 3), label, text);
  }
  for (double v = std::ceil(axes.y_min / ys) * ys; v <= axes.y_max + 1e-9 * yr; v += ys) {
    const ImVec2 p = frame.ToScreen(axes.x_min, v);
    draw->AddLine(ImVec2(lo.x, p.y), ImVec2(hi.x, p.y), grid);
    std::snprintf(text, sizeof text, "%g", std::abs(v) < 1e-9 * yr ? 0.0 : v);
    draw->AddText(ImVec2(lo.x - ImGui::CalcTextSize(text).x - 4, p.y - 7), label, text);
  }
  draw->AddRect(lo, hi, IM_COL32(120, 124, 130, 255));
  draw->AddText(ImVec2(lo.x, origin.y + 2), IM_COL32(235, 235, 235, 255), axes.title.c_str());
  draw->AddText(ImVec2((lo.x + hi.x - ImGui::CalcTextSize(axes.x_label.c_str()).x) / 2, hi.y + 17), label,
                axes.x_label.c_str());
  draw->AddText(ImVec2(hi.x - ImGui::CalcTextSize(axes.y_label.c_str()).x, origin.y + 2), label, axes.y_label.c_str());
}

void DrawPlotSeries(ImDrawList* draw, const PlotSeries& series, const PlotFrame& frame, unsigned colour_abgr) {
  const std::size_t n = series.size;
  auto point = [&](std::size_t i) { return frame.ToScreen(series.x(i), series.y(i)); };
  if (n >= 2) {
    // At most ~2 points per pixel column: long histories stay cheap to draw.
    const std::size_t stride =
        std::max<std::size_t>(1, n / static_cast<std::size_t>(2 * (frame.hi.x - frame.lo.x) + 1));
    std::vector<ImVec2> points;
    points.reserve(n / stride + 2);
    for (std::size_t i = 0; i < n; i += stride) points.push_back(point(i));
    points.push_back(point(n - 1));
    draw->AddPolyline(points.data(), static_cast<int>(points.size()), colour_abgr, 0, 2.0f);
  }
  if (n >= 1) draw->AddCircleFilled(point(n - 1), 4.0f, colour_abgr);
}

}  // namespace

void PlotLine(const char* id, const PlotAxes& axes, const PlotSeries& series, float width_px, float height_px,
              unsigned colour_abgr) {
  ImGui::PushID(id);
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  if (width_px <= 0.0f) width_px = ImGui::GetContentRegionAvail().x;
  ImDrawList* draw = ImGui::GetWindowDrawList();
  const float left = 52.0f, bottom = 34.0f, top = 20.0f, right = 10.0f;
  const PlotFrame frame{ImVec2(origin.x + left, origin.y + top),
                        ImVec2(origin.x + width_px - right, origin.y + height_px - bottom),
                        axes.x_min,
                        axes.y_min,
                        std::max(axes.x_max - axes.x_min, 1e-12),
                        std::max(axes.y_max - axes.y_min, 1e-12)};
  draw->AddRectFilled(frame.lo, frame.hi, IM_COL32(24, 26, 30, 255));
  DrawPlotAxes(draw, axes, frame, origin);
  draw->PushClipRect(frame.lo, frame.hi, true);
  DrawPlotSeries(draw, series, frame, colour_abgr);
  draw->PopClipRect();
  ImGui::Dummy(ImVec2(width_px, height_px));
  ImGui::PopID();
}

}  // namespace hapsim::gui
