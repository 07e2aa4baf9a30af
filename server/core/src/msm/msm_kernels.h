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
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include <Eigen/Core>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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

// Byte offset of node i's first coordinate in a 3 x n double array, 24 i
// (i >= 0). Read as unsigned, the 32-bit index zero-extends for free, and one
// offset then addresses x, v and f alike (a signed element index cost a sign
// extension and a separate scaling per array and spring end).
inline std::size_t NodeByteOffset(std::int32_t i) { return std::size_t{static_cast<std::uint32_t>(i)} * 24u; }

// p advanced by `bytes` bytes.
template <class T>
T* ByteOffset(T* p, std::size_t bytes) {
  using Byte = std::conditional_t<std::is_const_v<T>, const char, char>;
  return reinterpret_cast<T*>(reinterpret_cast<Byte*>(p) + bytes);
}

// Adds [k (l - L0) + c (v_j - v_i)·u] u to f_i and its negative to f_j,
// written as F = [k (1 - L0/l) + c ((v_j - v_i)·d) / l^2] d with d = x_j - x_i:
// one sqrt and one division per spring, and a short dependency chain after
// them (this form measured ~10 % faster than the textbook one).
//
// The loop is instruction-bound (~20 cycles per spring at ~3.8 IPC), so on
// x86-64 it computes two springs per iteration, one per SSE2 lane (SSE2 is
// part of baseline x86-64, no -march needed): one packed sqrt, divide and
// set of multiplies serve both springs (68 instead of 77 instructions per
// spring). Each lane performs the same IEEE operations in the same order as
// the scalar spring() below, so forces are bit-identical to it. Only the
// arithmetic is paired: loads are scalar into lanes (no gathers, which
// measured slower), and the scatter into f stays scalar and in spring order
// (spring a fully, then spring b), because consecutive springs may share a
// node.
template <class Springs>
inline void SpringForces(const MsmModel& m, const double* __restrict x, const double* __restrict v,
                         double* __restrict f, Springs springs) {
  const std::int32_t* __restrict si = m.spring_i.data();
  const std::int32_t* __restrict sj = m.spring_j.data();
  const double* __restrict rest = m.spring_rest_m.data();
  const double* __restrict ks = m.spring_k_N_per_m.data();
  const double* __restrict cs = m.spring_c_Ns_per_m.data();

  // One spring, scalar: the reference form, the odd last spring and the
  // non-SSE2 build.
  auto spring = [&](const std::int32_t s) __attribute__((always_inline)) {
    const std::size_t bi = NodeByteOffset(si[s]), bj = NodeByteOffset(sj[s]);
    const double* xi = ByteOffset(x, bi);
    const double* xj = ByteOffset(x, bj);
    const double* vi = ByteOffset(v, bi);
    const double* vj = ByteOffset(v, bj);
    double* fi = ByteOffset(f, bi);
    double* fj = ByteOffset(f, bj);
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
  };

  std::int32_t k = 0;
#if defined(__SSE2__)
  // (value for spring a, value for spring b): p[c] at byte offsets a and b.
  auto pair = [](const double* p, std::size_t a, std::size_t b, int c) __attribute__((always_inline)) {
    return _mm_loadh_pd(_mm_load_sd(ByteOffset(p, a) + c), ByteOffset(p, b) + c);
  };
  const __m128d one = _mm_set1_pd(1.0), tiny = _mm_set1_pd(kTinyLength2_m2);
  for (; k + 1 < springs.size(); k += 2) {
    const std::int32_t sa = springs[k], sb = springs[k + 1];
    const std::size_t ai = NodeByteOffset(si[sa]), aj = NodeByteOffset(sj[sa]);
    const std::size_t bi = NodeByteOffset(si[sb]), bj = NodeByteOffset(sj[sb]);
    // The same expressions as spring(), two lanes at a time.
    __m128d d[3], dv[3];
    for (int c = 0; c < 3; ++c) {
      d[c] = _mm_sub_pd(pair(x, aj, bj, c), pair(x, ai, bi, c));
      dv[c] = _mm_sub_pd(pair(v, aj, bj, c), pair(v, ai, bi, c));
    }
    const __m128d l2 = _mm_add_pd(
        _mm_add_pd(_mm_add_pd(_mm_mul_pd(d[0], d[0]), _mm_mul_pd(d[1], d[1])), _mm_mul_pd(d[2], d[2])), tiny);
    const __m128d inv_l = _mm_div_pd(one, _mm_sqrt_pd(l2));
    const __m128d d_dot_dv =
        _mm_add_pd(_mm_add_pd(_mm_mul_pd(d[0], dv[0]), _mm_mul_pd(d[1], dv[1])), _mm_mul_pd(d[2], dv[2]));
    const __m128d k_ab = _mm_loadh_pd(_mm_load_sd(ks + sa), ks + sb);
    const __m128d rest_ab = _mm_loadh_pd(_mm_load_sd(rest + sa), rest + sb);
    const __m128d c_ab = _mm_loadh_pd(_mm_load_sd(cs + sa), cs + sb);
    const __m128d scale = _mm_add_pd(_mm_mul_pd(k_ab, _mm_sub_pd(one, _mm_mul_pd(rest_ab, inv_l))),
                                     _mm_mul_pd(_mm_mul_pd(c_ab, d_dot_dv), _mm_mul_pd(inv_l, inv_l)));  // |F| / l
    double fa[3], fb[3];
    for (int c = 0; c < 3; ++c) {
      const __m128d fc = _mm_mul_pd(scale, d[c]);
      fa[c] = _mm_cvtsd_f64(fc);
      fb[c] = _mm_cvtsd_f64(_mm_unpackhi_pd(fc, fc));
    }
    // Scatter in spring order: a then b (they may share a node).
    for (int c = 0; c < 3; ++c) ByteOffset(f, ai)[c] += fa[c];
    for (int c = 0; c < 3; ++c) ByteOffset(f, aj)[c] -= fa[c];
    for (int c = 0; c < 3; ++c) ByteOffset(f, bi)[c] += fb[c];
    for (int c = 0; c < 3; ++c) ByteOffset(f, bj)[c] -= fb[c];
  }
#endif
  for (; k < springs.size(); ++k) spring(springs[k]);
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
