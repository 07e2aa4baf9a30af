// Scalpel strokes for the cutting scene's tests.
#pragma once
#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "hapsim/core/scenes/scene.h"
#include "scene_tick.h"

namespace hapsim::core::test {

// A scalpel stroke as the synthetic device's `cut` script draws it: approach
// from 5 mm above at speed, press to depth, draw `length` along `heading`,
// lift; the blade leans 30° back against the stroke.
inline std::vector<ToolInput> ScalpelStroke(Eigen::Vector2d entry, double heading_rad, double length_m,
                                            double depth_m = 0.0015, double speed_m_per_s = 0.01) {
  std::vector<ToolInput> out;
  const Eigen::Vector2d d(std::cos(heading_rad), std::sin(heading_rad));
  const Eigen::Vector3d up(-0.5 * d.x(), -0.5 * d.y(), std::sqrt(0.75));
  const Eigen::Quaterniond q = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), up);
  auto add = [&](Eigen::Vector3d tip, Eigen::Vector3d v) {
    ToolInput t;
    t.valid = true;
    t.tip_W_m = tip;
    t.orientation_W = q;
    t.velocity_W_m_per_s = v;
    out.push_back(t);
  };
  const double step = speed_m_per_s * kTick_s;
  for (double z = 0.005; z > -depth_m; z -= step) add({entry.x(), entry.y(), z}, {0, 0, -speed_m_per_s});
  for (double u = 0.0; u <= length_m; u += step)
    add({entry.x() + u * d.x(), entry.y() + u * d.y(), -depth_m}, {speed_m_per_s * d.x(), speed_m_per_s * d.y(), 0});
  const Eigen::Vector2d end = entry + length_m * d;
  for (double z = -depth_m; z < 0.005; z += step) add({end.x(), end.y(), z}, {0, 0, speed_m_per_s});
  return out;
}

}  // namespace hapsim::core::test
