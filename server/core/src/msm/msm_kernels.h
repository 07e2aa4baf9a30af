// Internal: the MSM force kernels shared by ComputeForces() and every
// integrator. Templated on the index range so the full update is a plain
// dense loop (no indirection the compiler cannot see through) and the local
// update walks an index list with the same code.
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

// f_i = f_ext_i + f_residual_i + m_i g - D_i v_i  for i in nodes (overwrites f).
template <class Nodes>
inline void NodeForces(const MsmModel& m, const MsmState& s, const double* __restrict v,
                       double* __restrict f, Nodes nodes) {
  const double* __restrict fe = s.f_ext_N.data();
  const double* __restrict fr = s.f_residual_N.data();
  const double* __restrict mass = m.mass_kg.data();
  const double* __restrict damp = m.node_damping_Ns_per_m.data();
  const double gx = m.gravity_m_per_s2.x(), gy = m.gravity_m_per_s2.y(), gz = m.gravity_m_per_s2.z();
  for (std::int32_t k = 0; k < nodes.size(); ++k) {
    const std::int32_t i = nodes[k];
    const double mi = mass[i], di = damp[i];
    f[3 * i + 0] = fe[3 * i + 0] + fr[3 * i + 0] + mi * gx - di * v[3 * i + 0];
    f[3 * i + 1] = fe[3 * i + 1] + fr[3 * i + 1] + mi * gy - di * v[3 * i + 1];
    f[3 * i + 2] = fe[3 * i + 2] + fr[3 * i + 2] + mi * gz - di * v[3 * i + 2];
  }
}

// Adds [k (l - L0) + c (v_j - v_i)·u] u to f_i and its negative to f_j.
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
    const std::int32_t i = si[s], j = sj[s];
    const double dx = x[3 * j + 0] - x[3 * i + 0];
    const double dy = x[3 * j + 1] - x[3 * i + 1];
    const double dz = x[3 * j + 2] - x[3 * i + 2];
    const double inv_l = 1.0 / std::sqrt(dx * dx + dy * dy + dz * dz + kTinyLength2_m2);
    const double l = (dx * dx + dy * dy + dz * dz) * inv_l;
    const double dvx = v[3 * j + 0] - v[3 * i + 0];
    const double dvy = v[3 * j + 1] - v[3 * i + 1];
    const double dvz = v[3 * j + 2] - v[3 * i + 2];
    const double rate = (dvx * dx + dvy * dy + dvz * dz) * inv_l;  // (v_j - v_i)·u
    const double scale = (ks[s] * (l - rest[s]) + cs[s] * rate) * inv_l;  // |F| / l
    const double fx = scale * dx, fy = scale * dy, fz = scale * dz;
    f[3 * i + 0] += fx;
    f[3 * i + 1] += fy;
    f[3 * i + 2] += fz;
    f[3 * j + 0] -= fx;
    f[3 * j + 1] -= fy;
    f[3 * j + 2] -= fz;
  }
}

// Adds -k_a (x_i - p_a) - c_a v_i for each anchor.
template <class Anchors>
inline void AnchorForces(const MsmModel& m, const double* __restrict x, const double* __restrict v,
                         double* __restrict f, Anchors anchors) {
  const std::int32_t* __restrict an = m.anchor_node.data();
  const double* __restrict p = m.anchor_point_W_m.data();
  const double* __restrict ka = m.anchor_k_N_per_m.data();
  const double* __restrict ca = m.anchor_c_Ns_per_m.data();
  for (std::int32_t k = 0; k < anchors.size(); ++k) {
    const std::int32_t a = anchors[k];
    const std::int32_t i = an[a];
    for (int c = 0; c < 3; ++c)
      f[3 * i + c] -= ka[a] * (x[3 * i + c] - p[3 * a + c]) + ca[a] * v[3 * i + c];
  }
}

}  // namespace hapsim::core::detail
