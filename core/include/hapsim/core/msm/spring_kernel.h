// Which machine code computes the MSM spring forces. Every kernel performs the
// same IEEE operations in the same order per spring, so forces, states and
// state hashes are bit-identical whichever runs (tested); they differ only in
// speed. The step picks the fastest one the CPU supports; tests and the
// benchmark may pick one explicitly (MsmWorkspace::spring_kernel).
#pragma once

#include <optional>

namespace hapsim::core {

// Doubles per node in the spring-force accumulator (MsmWorkspace::f): x, y, z
// and a pad lane that is never read, so a node's force is one aligned vector.
inline constexpr int kSpringForceStride = 4;

enum class SpringKernel {
  kPortable,  // any CPU: scalar, or two springs per SSE2 register on x86-64
  kAvx512,    // x86-64 with AVX-512F/VL: four springs per 256-bit register
};

// The fastest kernel this CPU runs, or the one ForceSpringKernel chose.
SpringKernel BestSpringKernel();
// Makes BestSpringKernel() return `kernel` (which must be supported) for
// every workspace made from now on, in the whole process; std::nullopt goes
// back to the fastest. For tests and tools that check that another kernel
// gives the same states; the step itself never needs it.
void ForceSpringKernel(std::optional<SpringKernel> kernel);
// Whether this CPU (and this build) can run `kernel`.
bool SpringKernelSupported(SpringKernel kernel);
// "portable" or "avx512".
const char* SpringKernelName(SpringKernel kernel);

}  // namespace hapsim::core
