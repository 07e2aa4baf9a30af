#include "hapsim/core/haptics/local_force_model.h"

#include <algorithm>
#include <cmath>

#include "hapsim/core/math/portable_math.h"

namespace hapsim::core {

const char* ToString(ContactState s) {
  switch (s) {
    case ContactState::kFree: return "free";
    case ContactState::kContact: return "contact";
    case ContactState::kPunctured: return "punctured";
    case ContactState::kCutting: return "cutting";
  }
  return "unknown";
}

Eigen::Vector3d EvaluateLocalForce(const LocalForceModel& m, const Eigen::Vector3d& x,
                                   const Eigen::Vector3d& v) {
  const Eigen::Vector3d& n = m.normal_W;
  // A Coulomb level is a magnitude: a negative or NaN one from the wire
  // counts as none (else the drag would push along the motion, and the
  // stick clamp's bounds would cross).
  const double coulomb_N = std::max(0.0, m.drag_N);
  switch (m.state) {
    case ContactState::kFree:
      return m.feedforward_W_N;
    case ContactState::kContact:
    case ContactState::kCutting: {
      const double penetration_m = (m.anchor_W_m - x).dot(n);
      if (m.state == ContactState::kContact && m.release_penetration_m > 0.0 &&
          penetration_m >= m.release_penetration_m) {
        const Eigen::Vector3d r = x - m.anchor_W_m;
        return -m.release_stiffness_N_per_m * (r - r.dot(n) * n) - m.release_damping_Ns_per_m * v.dot(n) * n;
      }
      Eigen::Vector3d f = m.feedforward_W_N;
      if (penetration_m > 0.0)
        f += std::max(0.0, m.stiffness_N_per_m * penetration_m - m.damping_Ns_per_m * v.dot(n)) * n;
      if (m.state == ContactState::kCutting) {
        const Eigen::Vector3d& t = m.drag_direction_W;
        const double v_t = v.dot(t);
        f -= (coulomb_N * pmath::Tanh(v_t / kDragSmoothingSpeed_m_per_s) + m.drag_damping_Ns_per_m * v_t) * t;
      }
      return f;
    }
    case ContactState::kPunctured: {
      const Eigen::Vector3d r = x - m.anchor_W_m;
      const Eigen::Vector3d lateral = r - r.dot(n) * n;
      const double stick_N = std::clamp(m.stick_stiffness_N_per_m * (x - m.stick_W_m).dot(n), -coulomb_N, coulomb_N);
      const double tip_penetration_m = (m.tip_anchor_W_m - x).dot(n);
      const bool tip_layer_gave_way =
          m.tip_release_penetration_m > 0.0 && tip_penetration_m >= m.tip_release_penetration_m;
      const double tip_N = tip_layer_gave_way ? 0.0 : std::max(0.0, m.tip_stiffness_N_per_m * tip_penetration_m);
      return m.feedforward_W_N - m.stiffness_N_per_m * lateral - (m.damping_Ns_per_m * v.dot(n) + stick_N - tip_N) * n;
    }
  }
  return m.feedforward_W_N;
}

}  // namespace hapsim::core
