// ScopedFlushDenormals: while alive, the calling thread's floating-point
// unit flushes subnormal results to zero and reads subnormal inputs as zero
// (x86 MXCSR FTZ + DAZ; restored on exit).
//
// Why: a tissue relaxing back to rest takes its z coordinates and
// velocities geometrically towards 0, and for seconds their squares and
// products (spring lengths, damping, kinetic energy) are subnormal. Each
// subnormal operation costs ~100 cycles here: a relaxed 101 x 101
// tissue_block stepped at 0.52 ms instead of 0.15 ms (docs/scene-limits.md).
// Values below 2.2e-308 carry no physics; FTZ/DAZ are deterministic, and
// every spring kernel (SSE2, AVX-512) and the scalar code obey the same
// MXCSR, so results stay bit-identical across kernels and CPUs.
#pragma once

#if defined(__x86_64__) || defined(__SSE2__)
#include <xmmintrin.h>
#define HAPSIM_HAS_MXCSR 1
#endif

namespace hapsim::core::detail {

class ScopedFlushDenormals {
 public:
#ifdef HAPSIM_HAS_MXCSR
  ScopedFlushDenormals() : saved_(_mm_getcsr()) { _mm_setcsr(saved_ | kFlushToZero | kDenormalsAreZero); }
  ~ScopedFlushDenormals() { _mm_setcsr(saved_); }
#else
  ScopedFlushDenormals() = default;  // other CPUs: subnormals stay (slower, still correct)
#endif
  ScopedFlushDenormals(const ScopedFlushDenormals&) = delete;
  ScopedFlushDenormals& operator=(const ScopedFlushDenormals&) = delete;

 private:
#ifdef HAPSIM_HAS_MXCSR
  static constexpr unsigned kFlushToZero = 0x8000;     // MXCSR.FTZ
  static constexpr unsigned kDenormalsAreZero = 0x0040;  // MXCSR.DAZ
  unsigned saved_;
#endif
};

}  // namespace hapsim::core::detail
