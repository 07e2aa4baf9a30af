// Internal: symplectic Euler's node pass with one 256-bit vector [x y z 0]
// per node array entry (AVX-512F/VL masked loads and stores, so no access
// goes past a node's own 24 bytes). Used with SpringKernel::kAvx512.
//
// Per component it performs the same IEEE operations in the same order as
// FinalNodePass + the scalar update in explicit_schemes.h, so x and v are
// bit-identical to the portable path, and so is the kinetic energy (each
// node's v^2 is summed x, y, z like the scalar loop, and nodes in order).
// Only the position sum of the stability guard, which is read for
// finiteness alone, is accumulated per lane.
#pragma once
#include <cstdint>

#include "msm_kernels.h"
#include "step_common.h"

#if HAPSIM_MSM_AVX512_KERNEL
namespace hapsim::core::detail {

// Stores lanes x, y, z at p as a 16-byte and an 8-byte store. (A masked
// 256-bit store measured ~45 % slower for the whole pass: the next node's
// load overlaps its 32-byte footprint and waits for it to retire.)
__attribute__((target("avx512f,avx512vl"), always_inline)) inline void StoreXyz(double* p, __m256d xyz) {
  _mm_storeu_pd(p, _mm256_castpd256_pd128(xyz));
  _mm_store_sd(p + 2, _mm256_extractf128_pd(xyz, 1));
}

template <class R>
__attribute__((target("avx512f,avx512vl"))) void SymplecticNodePassAvx512(const NodeTerms& t, double* __restrict f,
                                                                        double* __restrict x,
                                                                        double* __restrict v, double h, R r,
                                                                        Guard& g) {
  const __mmask8 xyz = 0x7;
  const __m256d gravity = _mm256_maskz_loadu_pd(xyz, t.gravity);
  const __m256d zero = _mm256_setzero_pd();
  __m256d position_sum = zero;
  double mass_v2 = g.mass_v2;
  for (std::int32_t k = 0; k < r.active.size(); ++k) {
    const std::int32_t i = r.active[k];
    const std::size_t e = 3 * static_cast<std::size_t>(static_cast<std::uint32_t>(i));
    double* fi = f + kSpringForceStride * static_cast<std::size_t>(static_cast<std::uint32_t>(i));
    const __m256d xi = _mm256_maskz_loadu_pd(xyz, x + e);
    const __m256d vi = _mm256_maskz_loadu_pd(xyz, v + e);
    // f + f_ext + f_res + m g - D v - k_anchor x + (k p)_anchor, left to right.
    __m256d total = _mm256_add_pd(_mm256_load_pd(fi), _mm256_maskz_loadu_pd(xyz, t.f_ext + e));
    total = _mm256_add_pd(total, _mm256_maskz_loadu_pd(xyz, t.f_res + e));
    total = _mm256_add_pd(total, _mm256_mul_pd(_mm256_set1_pd(t.mass[i]), gravity));
    total = _mm256_sub_pd(total, _mm256_mul_pd(_mm256_set1_pd(t.damping[i]), vi));
    total = _mm256_sub_pd(total, _mm256_mul_pd(_mm256_set1_pd(t.anchor_k[i]), xi));
    total = _mm256_add_pd(total, _mm256_maskz_loadu_pd(xyz, t.anchor_kp + e));
    _mm256_store_pd(fi, zero);
    // v += (h / m) F; x += h v.
    const __m256d v_new = _mm256_add_pd(vi, _mm256_mul_pd(_mm256_set1_pd(h * t.inv_mass[i]), total));
    const __m256d x_new = _mm256_add_pd(xi, _mm256_mul_pd(_mm256_set1_pd(h), v_new));
    StoreXyz(v + e, v_new);
    StoreXyz(x + e, x_new);
    position_sum = _mm256_mask_add_pd(position_sum, xyz, position_sum, x_new);
    // v^2 = (vx^2 + vy^2) + vz^2, as the scalar loop sums it.
    const __m256d v2 = _mm256_mul_pd(v_new, v_new);
    const __m128d v2_xy = _mm256_castpd256_pd128(v2);
    const __m128d v2_sum = _mm_add_sd(_mm_add_sd(v2_xy, _mm_unpackhi_pd(v2_xy, v2_xy)), _mm256_extractf128_pd(v2, 1));
    mass_v2 += t.mass[i] * _mm_cvtsd_f64(v2_sum);
  }
  alignas(32) double lanes[4];
  _mm256_store_pd(lanes, position_sum);
  g.position_sum += lanes[0] + lanes[1] + lanes[2];
  g.mass_v2 = mass_v2;
}

}  // namespace hapsim::core::detail
#endif  // HAPSIM_MSM_AVX512_KERNEL
