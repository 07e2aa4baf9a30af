#include "hapsim/core/scenes/acupuncture/acupuncture_params.h"

#include <sstream>
#include <stdexcept>

namespace hapsim::core {

namespace {

ParamTable<AcupunctureParams> MakeAcupunctureTable() {
  using P = AcupunctureParams;
  ParamTable<P> t("acupuncture");
  t.Add({.name = "shf_lmax", .unit = "count", .min = 1, .max = AcupunctureLimits::kMaxShfLmax, .integer = true,
         .description = "degree Lmax of each layer's spherical-harmonic surface"},
        &P::shf_lmax)
      .Add({.name = "shf_samples", .unit = "count", .min = 16, .max = AcupunctureLimits::kMaxShfSamples,
            .integer = true, .description = "surface samples per SH fit (at least (shf_lmax+1)^2)"},
           &P::shf_samples)
      .Add({.name = "net_surface_ratio", .unit = "1", .min = 0.01, .max = 1e3,
            .description = "k_s / K of the force nets' surface springs"},
           &P::net_surface_ratio)
      .Add({.name = "net_prestretch", .unit = "1", .min = 0, .max = 1,
            .description = "pre-stretch of the surface springs: rest length L / (1 + prestretch)"},
           &P::net_prestretch)
      .Add({.name = "springback_eta0", .unit = "1", .min = 0, .max = 1,
            .description = "shape-matching damping eta at puncture (1: particles stay)"},
           &P::springback_eta0)
      .Add({.name = "springback_eta_rate_per_step", .unit = "1", .min = 0, .max = 1,
            .description = "eta_r: eta decreases by this each step after puncture"},
           &P::springback_eta_rate_per_step)
      .Add({.name = "tunnel_stiffness_N_per_m", .unit = "N/m", .min = 0, .max = 1e5,
            .description = "lateral needle-tunnel stiffness after puncture"},
           &P::tunnel_stiffness_N_per_m)
      .Add({.name = "render_stiffness_max_N_per_m", .unit = "N/m", .min = 1, .max = 1e5,
            .description = "cap on the contact stiffness sent to the device"},
           &P::render_stiffness_max_N_per_m)
      .Add({.name = "contact_damping_Ns_per_m", .unit = "N*s/m", .min = 0, .max = 100,
            .description = "damper in the device's local contact model"},
           &P::contact_damping_Ns_per_m)
      .Add({.name = "shaft_friction_law", .unit = "choice", .min = 0, .max = 1, .integer = true,
            .description = "0: the paper's viscous shaft damping only (Table 1); 1: stick-slip Coulomb + scaled viscous"},
           &P::shaft_friction_law)
      .Add({.name = "shaft_viscous_scale", .unit = "1", .min = 0, .max = 1,
            .description = "law 1: fraction of Table 1's viscous shaft damping kept beside the Coulomb friction"},
           &P::shaft_viscous_scale)
      .Add({.name = "shaft_stick_stiffness_N_per_m", .unit = "N/m", .min = 1, .max = 1e4,
            .description = "law 1: axial spring holding a sticking shaft (friction below the Coulomb level)"},
           &P::shaft_stick_stiffness_N_per_m)
      .Add({.name = "patch_size_m", .unit = "m", .min = 0.005, .max = 0.2,
            .description = "side of the displayed square of each layer surface"},
           &P::patch_size_m)
      .Add({.name = "patch_grid_nodes", .unit = "count", .min = 2, .max = AcupunctureLimits::kMaxPatchGridNodes,
            .integer = true, .description = "nodes per side of each displayed patch"},
           &P::patch_grid_nodes);
  const std::array<TissueLayer, kNumTissueLayers> table2 = PaperTissueLayers();
  for (std::size_t i = 0; i < kNumTissueLayers; ++i) {
    const std::string n = table2[i].name;
    t.Add({.name = n + "_thickness_m", .unit = "m", .min = 1e-5, .max = 0.05, .description = n + " layer thickness"},
          [i](const P& p) { return p.layers[i].thickness_m; }, [i](P& p, double v) { p.layers[i].thickness_m = v; })
        .Add({.name = n + "_K_N_per_m", .unit = "N/m", .min = 1e-3, .max = 1e6,
              .description = n + " force-net virtual spring stiffness K (Table 2)"},
             [i](const P& p) { return p.layers[i].virtual_K_N_per_m; },
             [i](P& p, double v) { p.layers[i].virtual_K_N_per_m = v; })
        .Add({.name = n + "_d_Ns_per_m2", .unit = "N*s/m^2", .min = 0, .max = 1e6,
              .description = n + " shaft damping d per metre inserted (Table 1)"},
             [i](const P& p) { return p.layers[i].damping_Ns_per_m2; },
             [i](P& p, double v) { p.layers[i].damping_Ns_per_m2 = v; })
        .Add({.name = n + "_shaft_coulomb_N_per_m", .unit = "N/m", .min = 0, .max = 1e3,
              .description = n + " Coulomb shaft friction per metre inserted (law 1; not in the paper)"},
             [i](const P& p) { return p.layers[i].shaft_coulomb_N_per_m; },
             [i](P& p, double v) { p.layers[i].shaft_coulomb_N_per_m = v; })
        .Add({.name = n + "_puncture_force_N", .unit = "N", .min = 0.01, .max = 2.5,
              .description = n + " force on the tip that pierces the layer, for a 0.3 mm needle (scales with its diameter)"},
             [i](const P& p) { return p.layers[i].puncture_force_N; },
             [i](P& p, double v) { p.layers[i].puncture_force_N = v; })
        .Add({.name = n + "_rings", .unit = "count", .min = 2, .max = AcupunctureLimits::kMaxRings, .integer = true,
              .description = n + " force-net rings w (Table 2)"},
             [i](const P& p) { return static_cast<double>(p.layers[i].rings_w); },
             [i](P& p, double v) { p.layers[i].rings_w = static_cast<int>(v); })
        .Add({.name = n + "_spacing_m", .unit = "m", .min = 1e-5, .max = 0.01,
              .description = n + " force-net spring length L (Table 2)"},
             [i](const P& p) { return p.layers[i].spacing_L_m; }, [i](P& p, double v) { p.layers[i].spacing_L_m = v; });
  }
  return t;
}

}  // namespace

const ParamTable<AcupunctureParams>& AcupunctureParamTable() {
  static const ParamTable<AcupunctureParams> table = MakeAcupunctureTable();
  return table;
}

AcupunctureParams ParseAcupunctureParams(const std::map<std::string, double>& params) {
  const AcupunctureParams p = AcupunctureParamTable().Parse(params);
  // A least-squares fit of (Lmax+1)^2 coefficients needs at least as many samples.
  const int coefficients = (p.shf_lmax + 1) * (p.shf_lmax + 1);
  if (p.shf_samples < coefficients) {
    std::ostringstream msg;
    msg << "acupuncture: parameter 'shf_samples' = " << p.shf_samples << " must be in [" << coefficients << ", "
        << AcupunctureLimits::kMaxShfSamples << "] for 'shf_lmax' = " << p.shf_lmax
        << " (at least (shf_lmax+1)^2 samples per fit)";
    throw std::invalid_argument(msg.str());
  }
  // Nested layers need room below: the muscle bottom must stay inside the body.
  double total_m = 0.0;
  for (const auto& l : p.layers) total_m += l.thickness_m;
  if (total_m > 0.06)
    throw std::invalid_argument("acupuncture: total layer thickness must be <= 0.06 m (the limb radius is ~0.07 m)");
  return p;
}

}  // namespace hapsim::core
