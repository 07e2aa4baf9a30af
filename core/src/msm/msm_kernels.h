// Internal: the MSM force kernels shared by ComputeForces() and every
// integrator. Templated on the index range so the full update is a plain
// dense loop and the local update walks an index list with the same code.
//
// Forces are split in two so a step makes only two passes over memory:
//  - SpringForces() scatters the spring forces into an accumulator f that
//    is zero on entry;
//  - NodeTerms::Take() adds the per-node terms (external, residual, gravity,
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
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define HAPSIM_MSM_AVX512_KERNEL 1
#else
#define HAPSIM_MSM_AVX512_KERNEL 0
#endif

#include "hapsim/core/msm/msm_model.h"
#include "hapsim/core/msm/msm_state.h"
#include "hapsim/core/msm/spring_kernel.h"

namespace hapsim::core::detail {

// 0, 1, ..., n-1.
struct DenseRange {
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

// Byte offset of node i's first coordinate in a 3 x n double array (x, v):
// 24 i (i >= 0). Read as unsigned, the 32-bit index zero-extends for free,
// and one offset then addresses x and v alike (a signed element index cost a
// sign extension and a separate scaling per array and spring end).
inline std::size_t NodeByteOffset(std::int32_t i) { return std::size_t{static_cast<std::uint32_t>(i)} * 24u; }
// Byte offset of node i's entry in the spring-force accumulator: 32 i.
inline std::size_t AccumulatorByteOffset(std::int32_t i) {
  return std::size_t{static_cast<std::uint32_t>(i)} * (kSpringForceStride * sizeof(double));
}

// p advanced by `bytes` bytes.
template <class T>
T* ByteOffset(T* p, std::size_t bytes) {
  using Byte = std::conditional_t<std::is_const_v<T>, const char, char>;
  return reinterpret_cast<T*>(reinterpret_cast<Byte*>(p) + bytes);
}

// The spring force. Adds [k (l - L0) + c (v_j - v_i)·u] u to f_i and its
// negative to f_j, written as F = [k (1 - L0/l) + c ((v_j - v_i)·d) / l^2] d
// with d = x_j - x_i: one sqrt and one division per spring, and a short
// dependency chain after them (this form measured ~10 % faster than the
// textbook one).
//
// Three implementations of it (SpringKernel::kPortable is the first two)
// perform the same IEEE operations in the same order for every spring (no FMA contraction: the
// core builds with -ffp-contract=off) and scatter in spring order, so their
// forces are bit-identical:
//  - spring() below: one spring, scalar; the reference form.
//  - SpringForcesPortable: two springs per SSE2 register (baseline x86-64).
//  - SpringForcesAvx512: four springs per 256-bit register.
// The loop is instruction-bound in cache (the scalar form is ~77
// instructions per spring), so the wider kernels win by doing the
// arithmetic, loads and scatter of several springs in one instruction.
// Consecutive springs may share a node, so the scatter into f always
// completes spring a before spring b.

// Springs [first, springs.size()) two per iteration (SSE2) or one (scalar).
template <class Springs>
inline void SpringForcesPortable(const MsmModel& m, const double* __restrict x, const double* __restrict v,
                                 double* __restrict f, Springs springs, std::int32_t first) {
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
    double* fi = ByteOffset(f, AccumulatorByteOffset(si[s]));
    double* fj = ByteOffset(f, AccumulatorByteOffset(sj[s]));
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

  std::int32_t k = first;
#if defined(__SSE2__)
  // Two springs per iteration, one per SSE2 lane: one packed sqrt, divide and
  // set of multiplies serve both (68 instead of 77 instructions per spring).
  // Loads are scalar into lanes (gathers measured slower); the scatter is
  // scalar.
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
    double* fai = ByteOffset(f, AccumulatorByteOffset(si[sa]));
    double* faj = ByteOffset(f, AccumulatorByteOffset(sj[sa]));
    for (int c = 0; c < 3; ++c) fai[c] += fa[c];
    for (int c = 0; c < 3; ++c) faj[c] -= fa[c];
    double* fbi = ByteOffset(f, AccumulatorByteOffset(si[sb]));
    double* fbj = ByteOffset(f, AccumulatorByteOffset(sj[sb]));
    for (int c = 0; c < 3; ++c) fbi[c] += fb[c];
    for (int c = 0; c < 3; ++c) fbj[c] -= fb[c];
  }
#endif
  for (; k < springs.size(); ++k) spring(springs[k]);
}

#if HAPSIM_MSM_AVX512_KERNEL
#define HAPSIM_AVX512_FN __attribute__((target("avx512f,avx512vl"), always_inline)) inline

// Lane sums x + y + z of four vectors [x y z 0] (springs a..d), computed as
// (x + y) + z like the scalar form (adding the zero pad lane could turn a
// -0 into +0).
HAPSIM_AVX512_FN __m256d SumXyz4(__m256d a, __m256d b, __m256d c, __m256d d) {
  const __m256d ab_xz = _mm256_unpacklo_pd(a, b);                   // a.x b.x a.z b.z
  const __m256d ab_y0 = _mm256_unpackhi_pd(a, b);                   // a.y b.y 0 0
  const __m256d ab = _mm256_mask_add_pd(ab_xz, 0x3, ab_xz, ab_y0);  // a.x+a.y b.x+b.y a.z b.z
  const __m256d cd_xz = _mm256_unpacklo_pd(c, d);
  const __m256d cd_y0 = _mm256_unpackhi_pd(c, d);
  const __m256d cd = _mm256_mask_add_pd(cd_xz, 0x3, cd_xz, cd_y0);
  return _mm256_add_pd(_mm256_permute2f128_pd(ab, cd, 0x20),   // (x + y) of a b c d
                       _mm256_permute2f128_pd(ab, cd, 0x31));  // z of a b c d
}

// A per-spring parameter for springs s[0..3] (consecutive for DenseRange).
template <class Springs>
HAPSIM_AVX512_FN __m256d LoadSpringParam4(const double* p, const std::int32_t* s) {
  if constexpr (std::is_same_v<Springs, DenseRange>) return _mm256_loadu_pd(p + s[0]);
  else return _mm256_set_pd(p[s[3]], p[s[2]], p[s[1]], p[s[0]]);
}

// f_i += scale[lane] d, f_j -= scale[lane] d: one spring's scatter.
template <int kLane>
HAPSIM_AVX512_FN void ScatterSpring4(double* f, std::size_t acc_i, std::size_t acc_j, __m256d scale, __m256d d) {
  const __m256d force = _mm256_mul_pd(_mm256_permute4x64_pd(scale, kLane * 0x55), d);  // pad lane: 0 * scale
  double* fi = ByteOffset(f, acc_i);
  double* fj = ByteOffset(f, acc_j);
  _mm256_store_pd(fi, _mm256_add_pd(_mm256_load_pd(fi), force));
  _mm256_store_pd(fj, _mm256_sub_pd(_mm256_load_pd(fj), force));
}

// Four springs per iteration: each spring end's x and v are one masked
// 256-bit load [x y z 0] (the mask stops the load at the node's own 24
// bytes, so the last node never reads past its array), the lengths and dot
// products are summed across lanes into one register per quantity, sqrt,
// divide and the scale run once for the four springs, and each spring's
// force is one 256-bit add into the 32-byte accumulator entry. Processes
// the largest multiple of four springs; returns how many.
template <class Springs>
__attribute__((target("avx512f,avx512vl"))) std::int32_t SpringForcesAvx512(const MsmModel& m,
                                                                           const double* __restrict x,
                                                                           const double* __restrict v,
                                                                           double* __restrict f, Springs springs) {
  const std::int32_t* __restrict si = m.spring_i.data();
  const std::int32_t* __restrict sj = m.spring_j.data();
  const double* __restrict rest = m.spring_rest_m.data();
  const double* __restrict ks = m.spring_k_N_per_m.data();
  const double* __restrict cs = m.spring_c_Ns_per_m.data();
  const __mmask8 xyz = 0x7;
  const __m256d one = _mm256_set1_pd(1.0), tiny = _mm256_set1_pd(kTinyLength2_m2);
  std::int32_t k = 0;
  for (; k + 3 < springs.size(); k += 4) {
    std::int32_t s[4];
    std::size_t acc_i[4], acc_j[4];
    __m256d d[4], d2[4], d_dv[4];
    for (int q = 0; q < 4; ++q) {
      s[q] = springs[k + q];
      const std::int32_t i = si[s[q]], j = sj[s[q]];
      acc_i[q] = AccumulatorByteOffset(i);
      acc_j[q] = AccumulatorByteOffset(j);
      const std::size_t bi = NodeByteOffset(i), bj = NodeByteOffset(j);
      d[q] = _mm256_sub_pd(_mm256_maskz_loadu_pd(xyz, ByteOffset(x, bj)), _mm256_maskz_loadu_pd(xyz, ByteOffset(x, bi)));
      const __m256d dv = _mm256_sub_pd(_mm256_maskz_loadu_pd(xyz, ByteOffset(v, bj)),
                                       _mm256_maskz_loadu_pd(xyz, ByteOffset(v, bi)));
      d2[q] = _mm256_mul_pd(d[q], d[q]);
      d_dv[q] = _mm256_mul_pd(d[q], dv);
    }
    const __m256d l2 = _mm256_add_pd(SumXyz4(d2[0], d2[1], d2[2], d2[3]), tiny);
    const __m256d d_dot_dv = SumXyz4(d_dv[0], d_dv[1], d_dv[2], d_dv[3]);
    const __m256d inv_l = _mm256_div_pd(one, _mm256_sqrt_pd(l2));
    const __m256d k4 = LoadSpringParam4<Springs>(ks, s);
    const __m256d rest4 = LoadSpringParam4<Springs>(rest, s);
    const __m256d c4 = LoadSpringParam4<Springs>(cs, s);
    const __m256d scale = _mm256_add_pd(_mm256_mul_pd(k4, _mm256_sub_pd(one, _mm256_mul_pd(rest4, inv_l))),
                                        _mm256_mul_pd(_mm256_mul_pd(c4, d_dot_dv), _mm256_mul_pd(inv_l, inv_l)));
    ScatterSpring4<0>(f, acc_i[0], acc_j[0], scale, d[0]);
    ScatterSpring4<1>(f, acc_i[1], acc_j[1], scale, d[1]);
    ScatterSpring4<2>(f, acc_i[2], acc_j[2], scale, d[2]);
    ScatterSpring4<3>(f, acc_i[3], acc_j[3], scale, d[3]);
  }
  return k;
}
#undef HAPSIM_AVX512_FN
#endif  // HAPSIM_MSM_AVX512_KERNEL

// Spring forces at (x, v) scattered into the accumulator f (zero on entry
// for the springs' nodes), with `kernel` where this CPU supports it.
template <class Springs>
inline void SpringForces(const MsmModel& m, SpringKernel kernel, const double* x, const double* v, double* f,
                         Springs springs) {
  std::int32_t done = 0;
#if HAPSIM_MSM_AVX512_KERNEL
  if (kernel == SpringKernel::kAvx512 && SpringKernelSupported(kernel)) done = SpringForcesAvx512(m, x, v, f, springs);
#else
  (void)kernel;
#endif
  SpringForcesPortable(m, x, v, f, springs, done);
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

  // Total force component c on node i at (x, v) with spring force
  // spring_f_N on it: the spring force plus the node terms.
  double Total(double spring_f_N, const double* __restrict x, const double* __restrict v, std::int32_t i, int c) const {
    const std::int32_t e = 3 * i + c;
    return spring_f_N + f_ext[e] + f_res[e] + mass[i] * gravity[c] - damping[i] * v[e] - anchor_k[i] * x[e] +
           anchor_kp[e];
  }

  // Total() with the accumulated spring force f (kSpringForceStride per
  // node). Resets the accumulator entry to zero.
  double Take(double* __restrict f, const double* __restrict x, const double* __restrict v, std::int32_t i,
              int c) const {
    double& spring_f = f[kSpringForceStride * i + c];
    const double total = Total(spring_f, x, v, i, c);
    spring_f = 0.0;
    return total;
  }
};

}  // namespace hapsim::core::detail
