#include "hapsim/core/cutting/incision_curve.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace hapsim::core {

Eigen::Vector2d BezierPoint(const BezierControls& p, double a) {
  const double b = 1.0 - a;
  // B0 = (1-a)^3, B1 = 3a(1-a)^2, B2 = 3a^2(1-a), B3 = a^3 (eq. 7).
  return (b * b * b) * p[0] + (3.0 * a * b * b) * p[1] + (3.0 * a * a * b) * p[2] + (a * a * a) * p[3];
}

Eigen::Vector2d BezierDerivative(const BezierControls& p, double a) {
  const double b = 1.0 - a;
  return 3.0 * (b * b) * (p[1] - p[0]) + 6.0 * (a * b) * (p[2] - p[1]) + 3.0 * (a * a) * (p[3] - p[2]);
}

void IncisionCurve::Start(const Eigen::Vector2d& q) {
  segments_.clear();
  first_ = last_ = q;
  last_tangent_.setZero();
  started_ = true;
}

bool IncisionCurve::Extend(const Eigen::Vector2d& q) {
  if (!started_ || segments_.size() == segments_.capacity() || (q - last_).squaredNorm() == 0.0) return false;
  const Eigen::Vector2d chord = q - last_;
  const Eigen::Vector2d start_tangent = segments_.empty() ? chord : last_tangent_;
  segments_.push_back({last_, last_ + start_tangent / 3.0, q - chord / 3.0, q});  // within reserved capacity
  last_tangent_ = chord;
  last_ = q;
  return true;
}

namespace {
// Segment index and local parameter of curve parameter s (clamped).
std::pair<int, double> SplitIncisionParameter(double s, int segments) {
  s = std::clamp(s, 0.0, static_cast<double>(segments));
  const int k = std::min(static_cast<int>(s), segments - 1);
  return {k, s - k};
}

// IncisionCurve::Project's steps for one segment p, in order.

// The best of 17 evenly spaced samples of p: a start for Newton's method
// near the global minimum.
double SampledClosestBezierParameter(const BezierControls& p, const Eigen::Vector2d& q) {
  constexpr int kSamples = 16;
  double a = 0.0, d2 = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= kSamples; ++i) {
    const double ai = static_cast<double>(i) / kSamples;
    const double di = (BezierPoint(p, ai) - q).squaredNorm();
    if (di < d2) {
      d2 = di;
      a = ai;
    }
  }
  return a;
}

// Four Newton steps on g(a) = (P - q)·P' from a, within [0, 1].
double RefineClosestBezierParameter(const BezierControls& p, const Eigen::Vector2d& q, double a) {
  for (int it = 0; it < 4; ++it) {
    const Eigen::Vector2d r = BezierPoint(p, a) - q;
    const Eigen::Vector2d d1 = BezierDerivative(p, a);
    const double b = 1.0 - a;
    const Eigen::Vector2d d2v = 6.0 * b * (p[2] - 2.0 * p[1] + p[0]) + 6.0 * a * (p[3] - 2.0 * p[2] + p[1]);
    const double g = r.dot(d1), dg = d1.squaredNorm() + r.dot(d2v);
    if (!(dg > 0.0)) break;
    a = std::clamp(a - g / dg, 0.0, 1.0);
  }
  return a;
}

// +1 when r lies to the left of the tangent t, -1 to the right, 0 on it.
int IncisionSide(const Eigen::Vector2d& t, const Eigen::Vector2d& r) {
  const double cross = t.x() * r.y() - t.y() * r.x();
  return cross > 0.0 ? 1 : (cross < 0.0 ? -1 : 0);
}

}  // namespace

Eigen::Vector2d IncisionCurve::Point(double s) const {
  if (segments_.empty()) return first_;
  const auto [k, a] = SplitIncisionParameter(s, Segments());
  return BezierPoint(segments_[static_cast<std::size_t>(k)], a);
}

Eigen::Vector2d IncisionCurve::Tangent(double s) const {
  if (segments_.empty()) return Eigen::Vector2d::UnitX();
  const auto [k, a] = SplitIncisionParameter(s, Segments());
  const Eigen::Vector2d d = BezierDerivative(segments_[static_cast<std::size_t>(k)], a);
  const double n = d.norm();
  return n > 0.0 ? Eigen::Vector2d(d / n) : Eigen::Vector2d::UnitX();
}

IncisionCurve::Projection IncisionCurve::Project(const Eigen::Vector2d& q, int first, int last) const {
  Projection best;
  if (segments_.empty()) {
    best.point = first_;
    best.distance_m = (q - first_).norm();
    return best;
  }
  first = std::clamp(first, 0, Segments() - 1);
  last = std::clamp(last, first, Segments() - 1);
  double best_d2 = std::numeric_limits<double>::infinity();
  for (int k = first; k <= last; ++k) {
    const BezierControls& p = segments_[static_cast<std::size_t>(k)];
    const double a = RefineClosestBezierParameter(p, q, SampledClosestBezierParameter(p, q));
    const double d2 = (BezierPoint(p, a) - q).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best.s = k + a;
    }
  }
  best.point = Point(best.s);
  best.distance_m = std::sqrt(best_d2);
  best.side = IncisionSide(Tangent(best.s), q - best.point);
  return best;
}

double IncisionCurve::Length_m() const {
  double length = 0.0;
  for (const auto& p : segments_) {
    constexpr int kPanels = 32;  // even
    double sum = 0.0;
    for (int i = 0; i <= kPanels; ++i) {
      const double w = (i == 0 || i == kPanels) ? 1.0 : (i % 2 ? 4.0 : 2.0);
      sum += w * BezierDerivative(p, static_cast<double>(i) / kPanels).norm();
    }
    length += sum / (3.0 * kPanels);
  }
  return length;
}

}  // namespace hapsim::core
