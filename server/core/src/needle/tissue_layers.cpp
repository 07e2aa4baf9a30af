#include "hapsim/core/needle/tissue_layers.h"

#include <algorithm>

namespace hapsim::core {

std::array<TissueLayer, kNumTissueLayers> PaperTissueLayers() {
  constexpr double kMm = 1e-3, kNPerMm = 1e3, kPerMm = 1e3;
  return {{
      {"skin", 0.8 * kMm, 0.16 * kNPerMm, 3.0 * kPerMm, 8, 2.0 * kMm},
      {"fat", 8.4 * kMm, 0.08 * kNPerMm, 1.0 * kPerMm, 4, 1.0 * kMm},
      {"muscle", 39.0 * kMm, 0.23 * kNPerMm, 3.0 * kPerMm, 10, 2.5 * kMm},
  }};
}

double ShaftDamping_Ns_per_m(const std::array<TissueLayer, kNumTissueLayers>& layers,
                             const double* depth_below_top_m, int punctured_layers) {
  double b = 0.0;
  for (int i = 0; i < std::min(punctured_layers, kNumTissueLayers); ++i) {
    const double h_m = std::clamp(depth_below_top_m[i], 0.0, layers[static_cast<std::size_t>(i)].thickness_m);
    b += layers[static_cast<std::size_t>(i)].damping_Ns_per_m2 * h_m;
  }
  return b;
}

}  // namespace hapsim::core
