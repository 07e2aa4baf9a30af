// Line plots drawn with ImGui's draw list (ImPlot is not packaged in
// Debian): axes with ticks and labels, one polyline, an optional marker.
#pragma once
#include <cstddef>
#include <functional>
#include <string>

namespace hapsim::gui {

struct PlotAxes {
  std::string title, x_label, y_label;
  double x_min = 0.0, x_max = 1.0, y_min = 0.0, y_max = 1.0;
};

// The points of a line, read where they are: point i is (x(i), y(i)) for
// i < size. A plot reads at most ~2 points per pixel column of them.
struct PlotSeries {
  std::size_t size = 0;
  std::function<double(std::size_t)> x, y;
};

// Draws at the cursor, size_px wide and high (0: the available width).
void PlotLine(const char* id, const PlotAxes& axes, const PlotSeries& series, float width_px, float height_px,
              unsigned colour_abgr = 0xff30c0ffu);

// "Nice" tick step for a range (1, 2 or 5 x 10^k) giving about `ticks` ticks.
double NiceTickStep(double range, int ticks);

}  // namespace hapsim::gui
