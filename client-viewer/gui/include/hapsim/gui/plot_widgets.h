// Line plots drawn with ImGui's draw list (ImPlot is not packaged in
// Debian): axes with ticks and labels, one polyline, an optional marker.
#pragma once
#include <string>
#include <vector>

namespace hapsim::gui {

struct PlotAxes {
  std::string title, x_label, y_label;
  double x_min = 0.0, x_max = 1.0, y_min = 0.0, y_max = 1.0;
};

// Draws at the cursor, size_px wide and high (0: the available width).
// x and y have the same length.
void PlotLine(const char* id, const PlotAxes& axes, const std::vector<double>& x, const std::vector<double>& y,
              float width_px, float height_px, unsigned colour_abgr = 0xff30c0ffu);

// "Nice" tick step for a range (1, 2 or 5 x 10^k) giving about `ticks` ticks.
double NiceTickStep(double range, int ticks);

}  // namespace hapsim::gui
