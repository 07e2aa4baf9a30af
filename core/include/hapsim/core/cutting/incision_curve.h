// Stage 2 of the cutting paper's three-stage cut: the incision drawn as a
// cubic Bézier curve (eqs. 5-7), P(a) = Σ_k P_k B_k,3(a) with
// B_k,3(a) = C(3,k) a^k (1-a)^(3-k), a in [0, 1]; it passes through P0 and
// P3 and "extends as the tool moves (control points added)". Here the
// incision is a chain of such cubic segments, one per committed blade
// position: segment k runs from the previous point Q_{k-1} to the new one
// Q_k with P1 = Q_{k-1} + T_{k-1}/3 and P2 = Q_k - T_k/3, where T_k = Q_k -
// Q_{k-1} (the chord, known when Q_k is committed) and T_{k-1} is the
// previous segment's end tangent — so the chain is C1 and a committed
// segment never changes (wound nodes already placed on it stay on it).
//
// Coordinates: the skin's rest plane (x, y) [m]. Curve parameter: s in
// [0, Segments()], segment floor(s) at a = s - floor(s); it grows along the
// incision.
#pragma once
#include <array>
#include <cstddef>
#include <vector>

#include <Eigen/Core>

namespace hapsim::core {

using BezierControls = std::array<Eigen::Vector2d, 4>;

// Eq. (5) with n = 3, the Bernstein weights of eq. (7).
Eigen::Vector2d BezierPoint(const BezierControls& p, double a);
Eigen::Vector2d BezierDerivative(const BezierControls& p, double a);  // dP/da

class IncisionCurve {
 public:
  explicit IncisionCurve(std::size_t max_segments = 0) { segments_.reserve(max_segments); }

  void Start(const Eigen::Vector2d& q);  // the first point; forgets any curve
  // Appends the segment to q. False (nothing changes) when the reserved
  // capacity is full or q coincides with the last point.
  bool Extend(const Eigen::Vector2d& q);
  void Clear() { segments_.clear(); started_ = false; }

  bool Started() const { return started_; }
  int Segments() const { return static_cast<int>(segments_.size()); }
  const BezierControls& Controls(int segment) const { return segments_[static_cast<std::size_t>(segment)]; }
  const Eigen::Vector2d& FirstPoint() const { return first_; }
  const Eigen::Vector2d& LastPoint() const { return last_; }
  Eigen::Vector2d Point(double s) const;
  Eigen::Vector2d Tangent(double s) const;  // unit

  struct Projection {
    double s = 0.0;              // curve parameter of the closest point
    Eigen::Vector2d point;       // the closest point
    double distance_m = 0.0;
    int side = 0;                // +1: q is left of the curve (seen from +z, along increasing s); -1 right; 0 on it
  };
  // The closest point to q on segments [first, last] (clamped to the
  // curve): 16 samples per segment, then Newton on (P - q)·P' = 0.
  Projection Project(const Eigen::Vector2d& q, int first_segment, int last_segment) const;
  // Arc length of segments [0, Segments()) by Simpson's rule (32 panels each).
  double Length_m() const;

 private:
  std::vector<BezierControls> segments_;
  Eigen::Vector2d first_ = Eigen::Vector2d::Zero(), last_ = Eigen::Vector2d::Zero();
  Eigen::Vector2d last_tangent_ = Eigen::Vector2d::Zero();
  bool started_ = false;
};

}  // namespace hapsim::core
