#include "hapsim/core/msm/spring_kernel.h"

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

SpringKernel BestSpringKernel() {
  return SpringKernelSupported(SpringKernel::kAvx512) ? SpringKernel::kAvx512 : SpringKernel::kPortable;
}

const char* SpringKernelName(SpringKernel kernel) {
  switch (kernel) {
    case SpringKernel::kPortable: return "portable";
    case SpringKernel::kAvx512: return "avx512";
  }
  return "unknown";
}

}  // namespace hapsim::core
