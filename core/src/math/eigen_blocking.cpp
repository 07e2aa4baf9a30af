#include "hapsim/core/math/eigen_blocking.h"

#include <Eigen/Core>

namespace hapsim::core {

void PinEigenBlockingSizes() {
  if (Eigen::l1CacheSize() == kEigenL1CacheBytes && Eigen::l2CacheSize() == kEigenL2CacheBytes &&
      Eigen::l3CacheSize() == kEigenL3CacheBytes)
    return;
  Eigen::setCpuCacheSizes(kEigenL1CacheBytes, kEigenL2CacheBytes, kEigenL3CacheBytes);
}

}  // namespace hapsim::core
