#include "hapsim/core/scenes/cutting/cutting_params.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace hapsim::core {

namespace {

ParamTable<CuttingParams> MakeCuttingTable() {
  using P = CuttingParams;
  ParamTable<P> t("cutting");
  t.Add({.name = "patch_length_m", .unit = "m", .min = 0.005, .max = 0.3, .description = "skin patch length (x)"},
        &P::patch_length_m)
      .Add({.name = "patch_width_m", .unit = "m", .min = 0.005, .max = 0.3, .description = "skin patch width (y)"},
           &P::patch_width_m)
      .Add(
          {.name = "spacing_m", .unit = "m", .min = 2e-4, .max = 0.005, .description = "grid spacing of the skin mesh"},
          &P::spacing_m)
      .Add({.name = "skin_thickness_m",
            .unit = "m",
            .min = 1e-4,
            .max = 0.01,
            .description = "skin thickness t (wound face area = t x edge length)"},
           &P::skin_thickness_m)
      .Add({.name = "damping_Ns_per_m",
            .unit = "N*s/m",
            .min = 0,
            .max = 100,
            .description = "D: absolute damping of every node (paper: 3 N*s/m on a coarser mesh)"},
           &P::damping_Ns_per_m)
      .Add({.name = "node_mass_kg",
            .unit = "kg",
            .min = 1e-4,
            .max = 1,
            .description = "mass of an interior node (lumped from an areal density)"},
           &P::node_mass_kg)
      .Add({.name = "anchor_stiffness_N_per_m",
            .unit = "N/m",
            .min = 0,
            .max = 1e4,
            .description = "in-plane: zero-length spring of each node to its rest position (skin over fascia)"},
           &P::anchor_stiffness_N_per_m)
      .Add({.name = "support_stiffness_N_per_m",
            .unit = "N/m",
            .min = 0,
            .max = 1e4,
            .description = "vertical spring of each node to its rest height (pressing the skin down)"},
           &P::support_stiffness_N_per_m)
      .Add({.name = "youngs_modulus_Pa",
            .unit = "Pa",
            .min = 1e3,
            .max = 1e7,
            .description = "E of the skin (paper: 20 kPa): the springs K = 3 E t / 8 and sigma_r = E eps_r"},
           &P::youngs_modulus_Pa)
      .Add({.name = "residual_strain",
            .unit = "1",
            .min = 0,
            .max = 0.5,
            .description = "eps_r: residual strain released by a cut (paper: 0.1)"},
           &P::residual_strain)
      .Add({.name = "blade_radius_m",
            .unit = "m",
            .min = 5e-5,
            .max = 0.005,
            .description = "radius r of the scalpel's collision cylinder"},
           &P::blade_radius_m)
      .Add({.name = "blade_length_m",
            .unit = "m",
            .min = 0.002,
            .max = 0.1,
            .description = "length of the blade's cylinder, from the tip along the tool"},
           &P::blade_length_m)
      .Add({.name = "sweep_radius_m",
            .unit = "m",
            .min = 1e-4,
            .max = 0.01,
            .description = "radius of stage 1's swept volume (>= spacing and blade radius)"},
           &P::sweep_radius_m)
      .Add({.name = "segment_length_m",
            .unit = "m",
            .min = 2e-4,
            .max = 0.02,
            .description = "blade travel per incision segment (>= spacing)"},
           &P::segment_length_m)
      .Add({.name = "cut_depth_m",
            .unit = "m",
            .min = 0,
            .max = 0.01,
            .description = "tip depth below the surface at which the blade starts cutting"},
           &P::cut_depth_m)
      .Add({.name = "contact_stiffness_N_per_m",
            .unit = "N/m",
            .min = 1,
            .max = 1e5,
            .description = "tip-skin penalty spring before the blade cuts"},
           &P::contact_stiffness_N_per_m)
      .Add({.name = "contact_damping_Ns_per_m",
            .unit = "N*s/m",
            .min = 0,
            .max = 100,
            .description = "tip-skin penalty damper"},
           &P::contact_damping_Ns_per_m)
      .Add({.name = "render_stiffness_max_N_per_m",
            .unit = "N/m",
            .min = 1,
            .max = 1e5,
            .description = "cap on the contact stiffness sent to the device"},
           &P::render_stiffness_max_N_per_m)
      .Add({.name = "cut_force_N",
            .unit = "N",
            .min = 0,
            .max = 3,
            .description = "Coulomb level of the drag felt while cutting"},
           &P::cut_force_N)
      .Add({.name = "cut_damping_Ns_per_m",
            .unit = "N*s/m",
            .min = 0,
            .max = 100,
            .description = "viscous part of the drag felt while cutting"},
           &P::cut_damping_Ns_per_m)
      .Add({.name = "max_kinetic_energy_J",
            .unit = "J",
            .min = 0,
            .max = 1e6,
            .min_open = true,
            .description = "a step above this kinetic energy is a blow-up: counted, and the scene resets"},
           &P::max_kinetic_energy_J)
      .Add({.name = "rest_force_N",
            .unit = "N",
            .min = 0,
            .max = 1e-5,
            .description = "skin under this net force (and rest_speed_m_per_s) rests out of the step until pulled; "
                           "0 = every node every step (error vs the full step measured up to 1e-5 N)"},
           &P::rest_force_N)
      .Add({.name = "rest_speed_m_per_s",
            .unit = "m/s",
            .min = 0,
            .max = 0.01,
            .description = "speed under which a skin node counts as quiet (it rests after 20 quiet steps)"},
           &P::rest_speed_m_per_s);
  return t;
}

}  // namespace

const ParamTable<CuttingParams>& CuttingParamTable() {
  static const ParamTable<CuttingParams> table = MakeCuttingTable();
  return table;
}

CuttingParams ParseCuttingParams(const std::map<std::string, double>& params) {
  const CuttingParams p = CuttingParamTable().Parse(params);
  const double nodes = (std::round(p.patch_length_m / p.spacing_m) + 1) * (std::round(p.patch_width_m / p.spacing_m) + 1);
  if (nodes > CuttingLimits::kMaxNodes) {
    std::ostringstream msg;
    msg << "cutting: parameters 'patch_length_m', 'patch_width_m' and 'spacing_m' give " << nodes
        << " grid nodes; the limit is " << CuttingLimits::kMaxNodes << " (a larger spacing or a smaller patch)";
    throw std::invalid_argument(msg.str());
  }
  if (p.sweep_radius_m < p.spacing_m || p.sweep_radius_m < p.blade_radius_m)
    throw std::invalid_argument("cutting: parameter 'sweep_radius_m' must be >= 'spacing_m' and >= 'blade_radius_m'");
  if (p.segment_length_m < p.spacing_m)
    throw std::invalid_argument("cutting: parameter 'segment_length_m' must be >= 'spacing_m'");
  return p;
}

}  // namespace hapsim::core
