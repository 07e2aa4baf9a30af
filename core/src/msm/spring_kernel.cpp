#include "hapsim/core/msm/spring_kernel.h"

#include <atomic>

#include "hapsim/core/assert.h"
#include "msm_kernels.h"

namespace hapsim::core {

namespace {

bool CpuHasAvx512Vl() {
#if HAPSIM_MSM_AVX512_KERNEL
  // libgcc checks the CPUID bits and that the OS saves the AVX-512 state.
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl");
#else
  return false;
#endif
}

}  // namespace

bool SpringKernelSupported(SpringKernel kernel) {
  static const bool avx512 = CpuHasAvx512Vl();
  switch (kernel) {
    case SpringKernel::kPortable: return true;
    case SpringKernel::kAvx512: return avx512;
  }
  return false;
}

namespace {
// -1: none forced; otherwise the forced SpringKernel's value.
std::atomic<int> forced_kernel{-1};
}  // namespace

SpringKernel BestSpringKernel() {
  const int forced = forced_kernel.load(std::memory_order_relaxed);
  if (forced >= 0) return static_cast<SpringKernel>(forced);
  return SpringKernelSupported(SpringKernel::kAvx512) ? SpringKernel::kAvx512 : SpringKernel::kPortable;
}

void ForceSpringKernel(std::optional<SpringKernel> kernel) {
  HAPSIM_DEMAND(!kernel || SpringKernelSupported(*kernel), "ForceSpringKernel: this CPU cannot run that kernel");
  forced_kernel.store(kernel ? static_cast<int>(*kernel) : -1, std::memory_order_relaxed);
}

const char* SpringKernelName(SpringKernel kernel) {
  switch (kernel) {
    case SpringKernel::kPortable: return "portable";
    case SpringKernel::kAvx512: return "avx512";
  }
  return "unknown";
}

}  // namespace hapsim::core
