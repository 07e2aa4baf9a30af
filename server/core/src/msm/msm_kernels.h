// Internal: the MSM force kernels shared by ComputeForces() and every
// integrator. Templated on the index range so the full update is a plain
// dense loop and the local update walks an index list with the same code.
//
// Forces are split in two so a step makes only two passes over memory:
//  - SpringForces() scatters the spring forces into an accumulator f that
//    is zero on entry;
//  - NodeForce() adds the per-node terms (external, residual, gravity,
//    absolute damping, anchors) when the integrator consumes f_i, and the
//    consumer resets f_i to zero for the next evaluation.
#pragma once
#include <cmath>
#include <cstdint>

#include <Eigen/Core>

#include "hapsim/core/msm/msm_model.h"
#include "hapsim/core/msm/msm_state.h"

namespace hapsim::core::detail {

// 0, 1, ..., n-1.
struct AllRange {
  std::int32_t n;
  std::int32_t size() const { return n; }
  std::int32_t operator[](std::int32_t k) const { return k; }
};
// An explicit list of indices.
struct ListRange {
  const std::int32_t* ids;
  std::int32_t n;
  std::int32_t size() const { return n; }
  std::int32_t operator[](std::int32_t k) const { return ids[k]; }
};

// Keeps 1/l finite for a degenerate (zero-length) spring without a branch:
// the force direction is then 0 instead of NaN.
constexpr double kTinyLength2_m2 = 1e-30;

// Adds [k (l - L0) + c (v_j - v_i)·u] u to f_i and its negative to f_j,
// written as F = [k (1 - L0/l) + c ((v_j - v_i)·d) / l^2] d with d = x_j - x_i:
// one sqrt and one division per spring, and a short dependency chain after
// them (the loop is latency-bound; this form measured ~10 % faster).
template <class Springs>
inline void SpringForces(const MsmModel& m, const double* __restrict x, const double* __restrict v,
                         double* __restrict f, Springs springs) {
  const std::int32_t* __restrict si = m.spring_i.data();
  const std::int32_t* __restrict sj = m.spring_j.data();
  const double* __restrict rest = m.spring_rest_m.data();
  const double* __restrict ks = m.spring_k_N_per_m.data();
  const double* __restrict cs = m.spring_c_Ns_per_m.data();
  for (std::int32_t k = 0; k < springs.size(); ++k) {
    const std::int32_t s = springs[k];
    const double* xi = x + 3 * si[s];
    const double* xj = x + 3 * sj[s];
    const double* vi = v + 3 * si[s];
    const double* vj = v + 3 * sj[s];
    double* fi = f + 3 * si[s];
    double* fj = f + 3 * sj[s];
    const double dx = xj[0] - xi[0], dy = xj[1] - xi[1], dz = xj[2] - xi[2];
    const double inv_l = 1.0 / std::sqrt(dx * dx + dy * dy + dz * dz + kTinyLength2_m2);
    const double d_dot_dv = dx * (vj[0] - vi[0]) + dy * (vj[1] - vi[1]) + dz * (vj[2] - vi[2]);
    const double scale = ks[s] * (1.0 - rest[s] * inv_l) + cs[s] * d_dot_dv * (inv_l * inv_l);  // |F| / l
    const double fx = scale * dx, fy = scale * dy, fz = scale * dz;
    fi[0] += fx;
    fi[1] += fy;
    fi[2] += fz;
    fj[0] -= fx;
    fj[1] -= fy;
    fj[2] -= fz;
  }
}

// Per-node force terms, read once per node.
struct NodeTerms {
  const double* __restrict f_ext;
  const double* __restrict f_res;
  const double* __restrict mass;
  const double* __restrict inv_mass;
  const double* __restrict damping;
  const double* __restrict anchor_k;
  const double* __restrict anchor_kp;
  double gravity[3];

  NodeTerms(const MsmModel& m, const MsmState& s)
      : f_ext(s.f_ext_N.data()),
        f_res(s.f_residual_N.data()),
        mass(m.mass_kg.data()),
        inv_mass(m.inv_mass_free_per_kg.data()),
        damping(m.absolute_damping_Ns_per_m.data()),
        anchor_k(m.anchor_k_sum_N_per_m.data()),
        anchor_kp(m.anchor_kp_sum_N.data()),
        gravity{m.gravity_m_per_s2.x(), m.gravity_m_per_s2.y(), m.gravity_m_per_s2.z()} {}

  // Total force component c on node i at (x, v): the accumulated spring
  // force f plus the node terms. Resets the accumulator entry to zero.
  double Take(double* __restrict f, const double* __restrict x, const double* __restrict v, std::int32_t i,
              int c) const {
    const std::int32_t e = 3 * i + c;
    const double total = f[e] + f_ext[e] + f_res[e] + mass[i] * gravity[c] - damping[i] * v[e] -
                         anchor_k[i] * x[e] + anchor_kp[e];
    f[e] = 0.0;
    return total;
  }
};

}  // namespace hapsim::core::detail
