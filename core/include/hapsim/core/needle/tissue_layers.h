// The acupuncture paper's three tissue layers (Table 2) in SI units, and the
// Table 1 shaft damping that accumulates layer by layer along the needle.
//
// [decide] Units of d (Table 1): the paper lists d in N·s/m but
// multiplies it by a depth h. We read d as damping per millimetre of shaft
// inserted: F = d [N·s/m per mm] · h [mm] · v [m/s], i.e. in SI
//   d_SI [N·s/m²] = d_paper · 1000.
// Skin (d = 3) then gives 3000 N·s/m² · 5 mm/s = 0.015 N per mm inserted
// at 5 mm/s — shaft friction of order 1e-2 N per mm, the order we target.
#pragma once
#include <array>
#include <string>

namespace hapsim::core {

inline constexpr int kNumTissueLayers = 3;

struct TissueLayer {
  std::string name;
  double thickness_m = 0.0;           // h_s, h_f, h_m
  double virtual_K_N_per_m = 0.0;     // K of the force net's virtual springs
  double damping_Ns_per_m2 = 0.0;     // d per unit inserted length (see above)
  int rings_w = 0;                    // w
  double spacing_L_m = 0.0;           // L
  // Coulomb shaft friction per metre of shaft inside the layer [N/m] — an
  // extension of Table 1 (its law is viscous only); see PaperTissueLayers.
  double shaft_coulomb_N_per_m = 0.0;
  // Normal force on the tip at which the layer's surface gives way, for a
  // 0.3 mm needle (the scene scales it with the needle's diameter) — in the
  // ranges of van Gerwen et al. 2012 (docs/validation.md#acupuncture).
  double puncture_force_N = 0.0;
};

// The needle diameter the layers' puncture forces are given for [m].
inline constexpr double kReferenceNeedleDiameter_m = 3e-4;

// Table 2: skin 0.8 mm / 0.16 N/mm / d 3 / w 8 / L 2 mm; fat 8.4 / 0.08 / 1 /
// 4 / 1; muscle 39 / 0.23 / 3 / 10 / 2.5. Shaft Coulomb friction (not in the
// paper; docs/validation.md#shaft-friction): skin 10, fat 5, muscle 15 N per
// metre inserted — of order 1e-2 N per mm, the order we target for
// shaft friction (0.36 N at 30 mm, above a Phantom Omni's ~0.26 N
// backdrive friction, so it is felt). Puncture forces (not in the paper's
// tables): skin 1.0 N, fat 0.2 N, muscle (fascia) 1.5 N.
std::array<TissueLayer, kNumTissueLayers> PaperTissueLayers();

// Table 1 damping along the shaft [N·s/m]: Σ_i d_i · h_i with h_i the length
// of shaft inside layer i, clamped to [0, thickness_i]. depth_below_top_m[i]
// is the tip's depth below the top of layer i; only the first
// punctured_layers layers count (a layer's surface must be pierced before
// its tissue grips the shaft).
double ShaftDamping_Ns_per_m(const std::array<TissueLayer, kNumTissueLayers>& layers,
                             const double* depth_below_top_m, int punctured_layers);
// The Coulomb level of shaft friction [N]: Σ_i coulomb_i · h_i, same h_i.
double ShaftCoulomb_N(const std::array<TissueLayer, kNumTissueLayers>& layers, const double* depth_below_top_m,
                      int punctured_layers);

}  // namespace hapsim::core
