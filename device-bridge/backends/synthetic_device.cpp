#include "backends/synthetic_device.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "hapsim/core/math/portable_math.h"

namespace hapsim::bridge {

void ValidateSyntheticScript(const SyntheticScript& s) {
  if (s.kind != "insertion" && s.kind != "constant_speed" && s.kind != "random_walk" && s.kind != "hold" &&
      s.kind != "cut") {
    throw std::invalid_argument("unknown synthetic script '" + s.kind +
                                "' (insertion, constant_speed, random_walk, hold, cut)");
  }
  if (!(s.cut_length_m > 0.0 && s.cut_length_m <= 0.3)) throw std::invalid_argument("cut length must be in (0, 0.3] m");
  if (!(std::abs(s.cut_bend_rad) <= 3.2 && std::isfinite(s.cut_angle_rad)))
    throw std::invalid_argument("cut bend must be within ±3.2 rad (±180°) and the angle finite");
  if (!(s.blade_tilt_rad >= 0.0 && s.blade_tilt_rad <= 1.2)) throw std::invalid_argument("blade tilt must be in [0, 1.2] rad");
  if (!(s.speed_m_per_s > 0.0 && s.speed_m_per_s <= 1.0)) throw std::invalid_argument("speed must be in (0, 1] m/s");
  if (!(s.depth_m >= 0.0 && s.depth_m <= 0.2)) throw std::invalid_argument("depth must be in [0, 0.2] m");
  if (!(s.start_height_m >= 0.0 && s.start_height_m <= 0.2)) throw std::invalid_argument("start height must be in [0, 0.2] m");
  if (!(s.hold_s >= 0.0 && s.hold_s <= 1e7)) throw std::invalid_argument("hold time must be in [0, 1e7] s");
  if (!(s.walk_step_m >= 0.0 && s.walk_radius_m >= 0.0)) throw std::invalid_argument("random-walk sizes must be >= 0");
  if (!s.entry_W_m.allFinite()) throw std::invalid_argument("entry point must be finite");
}

SyntheticDevice::SyntheticDevice(SyntheticScript script) : script_(std::move(script)), rng_(script_.seed) {
  const auto& s = script_;
  ValidateSyntheticScript(s);
  walk_W_m_ = s.entry_W_m + Eigen::Vector3d(0, 0, s.start_height_m);
}

double SyntheticDevice::ScriptHeight(const SyntheticScript& s, double t, const char** phase, double* vz) {
  const double v = s.speed_m_per_s;
  const double t_approach = s.start_height_m / v;  // start height -> surface
  const double t_press = s.depth_m / v;            // surface -> depth
  const double t_hold = s.kind == "insertion" ? s.hold_s : 0.0;
  const double t_out = (s.start_height_m + s.depth_m) / v;  // depth -> start height
  const double cycle = t_approach + t_press + t_hold + t_out;
  double tc = t;
  if (s.kind == "insertion") {
    tc = std::fmod(t, cycle);
  } else if (t >= cycle) {  // constant_speed runs once, then rests at the start height
    *phase = "done";
    *vz = 0.0;
    return s.start_height_m;
  }
  if (tc < t_approach) {
    *phase = "approach";
    *vz = -v;
    return s.start_height_m - v * tc;
  }
  tc -= t_approach;
  if (tc < t_press) {
    *phase = "press";
    *vz = -v;
    return -v * tc;
  }
  tc -= t_press;
  if (tc < t_hold) {
    *phase = "hold";
    *vz = 0.0;
    return -s.depth_m;
  }
  tc -= t_hold;
  *phase = "withdraw";
  *vz = v;
  return -s.depth_m + v * tc;
}

namespace {

// Along the cut stroke: arc length u -> point (from the entry point) and
// heading (a straight line or an arc of total turn cut_bend_rad).
Eigen::Vector2d CutStrokePoint(const SyntheticScript& s, double u, Eigen::Vector2d* heading) {
  const double a0 = s.cut_angle_rad, k = s.cut_bend_rad / s.cut_length_m;
  const double a = a0 + k * u;
  *heading = Eigen::Vector2d(core::pmath::Cos(a), core::pmath::Sin(a));
  if (std::abs(k) < 1e-9) return Eigen::Vector2d(u * core::pmath::Cos(a0), u * core::pmath::Sin(a0));
  return Eigen::Vector2d((core::pmath::Sin(a) - core::pmath::Sin(a0)) / k,
                         (core::pmath::Cos(a0) - core::pmath::Cos(a)) / k);
}

// Where the cut script is at time t: its phase, the arc length u along the
// stroke, the height z over the entry point, and their rates.
struct CutProgress {
  const char* phase = nullptr;
  double u = 0.0, z = 0.0, vz = 0.0, vu = 0.0;
  bool finished = false;
};

CutProgress CutProgressAt(const SyntheticScript& s, double t) {
  const double v = s.speed_m_per_s;
  const double t_approach = s.start_height_m / v, t_press = s.depth_m / v, t_draw = s.cut_length_m / v;
  const double t_lift = (s.start_height_m + s.depth_m) / v;
  CutProgress p;
  p.z = s.start_height_m;
  if (t < t_approach) {
    p.phase = "approach";
    p.z = s.start_height_m - v * t;
    p.vz = -v;
  } else if (t < t_approach + t_press) {
    p.phase = "press";
    p.z = -v * (t - t_approach);
    p.vz = -v;
  } else if (t < t_approach + t_press + t_draw) {
    p.phase = "cut";
    p.z = -s.depth_m;
    p.u = v * (t - t_approach - t_press);
    p.vu = v;
  } else if (t < t_approach + t_press + t_draw + t_lift) {
    p.phase = "lift";
    p.u = s.cut_length_m;
    p.z = -s.depth_m + v * (t - t_approach - t_press - t_draw);
    p.vz = v;
  } else {
    p.phase = "done";
    p.u = s.cut_length_m;
    p.finished = true;
  }
  return p;
}

// The blade's up axis (orientation * +z) leans back against the stroke.
Eigen::Quaterniond CutBladeOrientation(const SyntheticScript& s, const Eigen::Vector2d& heading) {
  const Eigen::Vector3d up(-core::pmath::Sin(s.blade_tilt_rad) * heading.x(),
                           -core::pmath::Sin(s.blade_tilt_rad) * heading.y(), core::pmath::Cos(s.blade_tilt_rad));
  return Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), up);
}

}  // namespace

DeviceReading SyntheticDevice::CutPose(const SyntheticScript& s, double t) {
  DeviceReading r;
  const CutProgress p = CutProgressAt(s, t);
  r.phase = p.phase;
  r.finished = p.finished;
  const Eigen::Vector2d entry = s.entry_W_m.head<2>();
  Eigen::Vector2d heading;
  const Eigen::Vector2d at = entry + CutStrokePoint(s, p.u, &heading);
  r.tip_W_m = Eigen::Vector3d(at.x(), at.y(), s.entry_W_m.z() + p.z);
  r.velocity_W_m_per_s = Eigen::Vector3d(p.vu * heading.x(), p.vu * heading.y(), p.vz);
  r.orientation_W = CutBladeOrientation(s, heading);
  return r;
}

DeviceReading SyntheticDevice::Read(double t_s) {
  DeviceReading r;
  const auto& s = script_;
  if (s.kind == "cut") return CutPose(s, t_s);
  if (s.kind == "hold") {
    r.tip_W_m = s.entry_W_m + Eigen::Vector3d(0, 0, s.start_height_m);
    r.phase = "hold";
    return r;
  }
  if (s.kind == "random_walk") {
    std::normal_distribution<double> step(0.0, s.walk_step_m);
    const Eigen::Vector3d previous = walk_W_m_;
    Eigen::Vector3d next = walk_W_m_ + Eigen::Vector3d(step(rng_), step(rng_), step(rng_));
    // Stay inside a box around the entry point, from the start height down to
    // the maximum depth, by reflecting at the walls.
    const Eigen::Vector3d lo = s.entry_W_m + Eigen::Vector3d(-s.walk_radius_m, -s.walk_radius_m, -s.depth_m);
    const Eigen::Vector3d hi = s.entry_W_m + Eigen::Vector3d(s.walk_radius_m, s.walk_radius_m, s.start_height_m);
    for (int k = 0; k < 3; ++k) {
      if (next[k] < lo[k]) next[k] = 2 * lo[k] - next[k];
      if (next[k] > hi[k]) next[k] = 2 * hi[k] - next[k];
      next[k] = std::clamp(next[k], lo[k], hi[k]);
    }
    const double dt = std::max(t_s - last_t_s_, 1e-6);
    r.velocity_W_m_per_s = (next - previous) / dt;
    walk_W_m_ = next;
    last_t_s_ = t_s;
    r.tip_W_m = next;
    r.phase = next.z() < s.entry_W_m.z() ? "inside" : "outside";
    return r;
  }
  double vz = 0.0;
  const double height = ScriptHeight(s, t_s, &r.phase, &vz);
  r.tip_W_m = s.entry_W_m + Eigen::Vector3d(0, 0, height);
  r.velocity_W_m_per_s = Eigen::Vector3d(0, 0, vz);
  r.finished = s.kind == "constant_speed" && r.phase == std::string_view("done");
  return r;
}

}  // namespace hapsim::bridge
