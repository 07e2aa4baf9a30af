// Parameters of the `acupuncture` scene (SceneSpec::params, SI, names with
// units): AcupunctureParamTable() declares each once (unit, range,
// description; defaults are AcupunctureParams{}, layers from Table 2 in
// tissue_layers.h). Every key is optional; unknown keys and out-of-range
// values throw std::invalid_argument naming the key.
//
// The SH fit (4 surfaces, SVD of shf_samples x (shf_lmax+1)^2) dominates the
// build, the patches and nets the tick: AcupunctureLimits keep the worst
// accepted combination under ~1 s to build and ~0.3 ms per tick
// (docs/scene-limits.md).
#pragma once
#include <array>
#include <map>
#include <string>

#include "hapsim/core/needle/tissue_layers.h"
#include "hapsim/core/scenes/param_table.h"

namespace hapsim::core {

struct AcupunctureLimits {
  static constexpr int kMaxShfLmax = 16;
  static constexpr int kMaxShfSamples = 3000;
  static constexpr int kMaxPatchGridNodes = 101;
  static constexpr int kMaxRings = 30;
};

struct AcupunctureParams {
  int shf_lmax = 8;
  int shf_samples = 600;
  double net_surface_ratio = 1.0;   // k_s / K of the force nets' surface springs
  double net_prestretch = 0.02;     // their pre-stretch (rest length L / 1.02)
  double springback_eta0 = 1.0;
  double springback_eta_rate_per_step = 0.02;
  double tunnel_stiffness_N_per_m = 300.0;
  // The Phantom Omni renders at most 1.02 N/mm stably on its weakest axis
  // (z; SensAble's specification: x 1.26, y 2.31, z 1.02 N/mm).
  double render_stiffness_max_N_per_m = 1000.0;
  double contact_damping_Ns_per_m = 0.5;
  // Shaft friction (docs/validation.md#shaft-friction). Law 0: Table 1's
  // viscous damping alone (the paper; what `hapsim-validate puncture`
  // checks). Law 1 (default): stick-slip Coulomb friction per layer plus a
  // tenth of Table 1's viscous part — Table 1 alone gives 7 N at 100 mm/s
  // and 30 mm depth, and nothing with the needle still.
  int shaft_friction_law = 1;
  double shaft_viscous_scale = 0.1;
  double shaft_stick_stiffness_N_per_m = 300.0;
  double patch_size_m = 0.06;
  int patch_grid_nodes = 41;
  double needle_length_m = 0.05;
  double needle_radius_m = 1.5e-4;  // 0.3 mm acupuncture needle
  std::array<TissueLayer, kNumTissueLayers> layers = PaperTissueLayers();
};

const ParamTable<AcupunctureParams>& AcupunctureParamTable();

// The table, then the cross-parameter rules: shf_samples >= (shf_lmax+1)^2
// and a total layer thickness <= 0.06 m.
AcupunctureParams ParseAcupunctureParams(const std::map<std::string, double>& params);

}  // namespace hapsim::core
