// Internal: what every MSM integrator shares — the index ranges a step
// works on (full or local update), the spring pass, stage copies and the
// stability-guard accumulators. Included only by msm_step.cpp.
#pragma once
#include <cstdint>

#include "msm_kernels.h"
#include "hapsim/core/msm/msm_step.h"
#include "hapsim/core/msm/msm_model.h"

namespace hapsim::core::detail {

// Index sets one step works on. Full update: active = touched = all nodes.
// Local update: active = integrated nodes; touched = active + frozen spring
// neighbours (their positions are read, their force entries are scratch).
template <class Nodes, class Springs, bool kLocal>
struct Ranges {
  Nodes active;
  Nodes touched;
  Springs springs;
  SpringPassListener* listener = nullptr;  // local update only
  static constexpr bool local = kLocal;
};

template <class Nodes>
void ZeroNodes(double* f, Nodes nodes) {
  for (std::int32_t k = 0; k < nodes.size(); ++k) {
    const std::int32_t i = nodes[k];
    f[3 * i] = f[3 * i + 1] = f[3 * i + 2] = 0.0;
  }
}

// Clears the spring-force accumulator entries of `nodes`.
template <class Nodes>
void ZeroAccumulator(double* f, Nodes nodes) {
  for (std::int32_t k = 0; k < nodes.size(); ++k)
    for (int c = 0; c < kSpringForceStride; ++c) f[kSpringForceStride * nodes[k] + c] = 0.0;
}

// Whether this step runs the AVX-512 kernels (chosen and supported).
inline bool UsesAvx512(const MsmWorkspace& ws) {
  return ws.spring_kernel == SpringKernel::kAvx512 && SpringKernelSupported(SpringKernel::kAvx512);
}

// Spring forces at (x, v) into the accumulator ws.f. Full update: f is all
// zero here (every consumer resets what it reads). Local update: frozen
// neighbours' entries may be stale, so the touched set is cleared first.
template <class R>
void SpringPass(const MsmModel& m, MsmWorkspace& ws, const double* x, const double* v, R r) {
  if constexpr (R::local) ZeroAccumulator(ws.f.data(), r.touched);
  detail::SpringForces(m, ws.spring_kernel, x, v, ws.f.data(), r.springs);
}

// Stage buffers start as a copy of the frozen neighbours' state (local
// only: in the full update the stage loop writes every node).
template <class R>
void CopyTouched(const double* x, const double* v, double* xs, double* vs, R r) {
  if constexpr (R::local) {
    for (std::int32_t k = 0; k < r.touched.size(); ++k) {
      const std::int32_t i = r.touched[k];
      for (int c = 0; c < 3; ++c) {
        xs[3 * i + c] = x[3 * i + c];
        vs[3 * i + c] = v[3 * i + c];
      }
    }
  }
}

// Stability guard accumulators, filled in each scheme's final node loop.
struct Guard {
  double position_sum = 0.0;  // NaN/inf anywhere propagates into it
  double mass_v2 = 0.0;       // sum m v^2 = 2 x kinetic energy
};

}  // namespace hapsim::core::detail
