#include "hapsim/core/needle/tissue_layers.h"

#include <algorithm>

namespace hapsim::core {

std::array<TissueLayer, kNumTissueLayers> PaperTissueLayers() {
  constexpr double kMm = 1e-3, kNPerMm = 1e3, kPerMm = 1e3;
  return {{
      {"skin", 0.8 * kMm, 0.16 * kNPerMm, 3.0 * kPerMm, 8, 2.0 * kMm, 10.0, 1.0},
      {"fat", 8.4 * kMm, 0.08 * kNPerMm, 1.0 * kPerMm, 4, 1.0 * kMm, 5.0, 0.2},
      {"muscle", 39.0 * kMm, 0.23 * kNPerMm, 3.0 * kPerMm, 10, 2.5 * kMm, 15.0, 1.5},
  }};
}

namespace {

// Σ_i per_length(layer i) · h_i over the punctured layers.
template <class PerLength>
double SumOverInsertedShaft(const std::array<TissueLayer, kNumTissueLayers>& layers, const double* depth_below_top_m,
                            int punctured_layers, PerLength per_length) {
  double sum = 0.0;
  for (int i = 0; i < std::min(punctured_layers, kNumTissueLayers); ++i) {
    const TissueLayer& layer = layers[static_cast<std::size_t>(i)];
    sum += per_length(layer) * std::clamp(depth_below_top_m[i], 0.0, layer.thickness_m);
  }
  return sum;
}

}  // namespace

double ShaftDamping_Ns_per_m(const std::array<TissueLayer, kNumTissueLayers>& layers,
                             const double* depth_below_top_m, int punctured_layers) {
  return SumOverInsertedShaft(layers, depth_below_top_m, punctured_layers,
                              [](const TissueLayer& l) { return l.damping_Ns_per_m2; });
}

double ShaftCoulomb_N(const std::array<TissueLayer, kNumTissueLayers>& layers, const double* depth_below_top_m,
                      int punctured_layers) {
  return SumOverInsertedShaft(layers, depth_below_top_m, punctured_layers,
                              [](const TissueLayer& l) { return l.shaft_coulomb_N_per_m; });
}

}  // namespace hapsim::core
