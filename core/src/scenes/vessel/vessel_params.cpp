#include "hapsim/core/scenes/vessel/vessel_params.h"

#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace hapsim::core {

namespace {


ParamTable<VesselParams> MakeVesselTable() {
  using P = VesselParams;
  ParamTable<P> t("vessel");
  t.Add({.name = "model",
         .unit = "code",
         .min = 0,
         .max = 2,
         .integer = true,
         .description = "the wall's model (the paper's, or a baseline on the same nodes)",
         .choices = {"meshless_xpbd", "mass_spring", "plain_pbd"}},
        &P::model)
      .Add({.name = "shape",
            .unit = "code",
            .min = 0,
            .max = 2,
            .integer = true,
            .description = "vessel along its centreline",
            .choices = {"straight (hand dorsal vein)", "bent (aortic arch)", "twice_bent (retinal arteriole)"}},
           &P::shape)
      .Add({.name = "length_m", .unit = "m", .min = 0, .max = 0.3, .description = "centreline length (0: the shape's)"},
           &P::length_m)
      .Add({.name = "lumen_radius_m",
            .unit = "m",
            .min = 0,
            .max = 0.02,
            .description = "inner radius of the wall (0: the shape's)"},
           &P::lumen_radius_m)
      .Add({.name = "wall_thickness_m",
            .unit = "m",
            .min = 0,
            .max = 0.005,
            .description = "wall thickness (0: the shape's)"},
           &P::wall_thickness_m)
      .Add({.name = "node_spacing_m",
            .unit = "m",
            .min = 0,
            .max = 0.01,
            .description = "meshless node spacing along and around the wall (0: the shape's)"},
           &P::node_spacing_m)
      .Add({.name = "radial_layers",
            .unit = "count",
            .min = 2,
            .max = 8,
            .description = "node rings across the wall, lumen to outer surface"},
           &P::radial_layers)
      .Add({.name = "youngs_modulus_Pa",
            .unit = "Pa",
            .min = 1e3,
            .max = 1e7,
            .description = "E of the wall (meshless elasticity)"},
           &P::youngs_modulus_Pa)
      .Add({.name = "poisson_ratio", .unit = "1", .min = 0, .max = 0.49, .description = "nu of the wall"},
           &P::poisson_ratio)
      .Add({.name = "density_kg_per_m3", .unit = "kg/m^3", .min = 500, .max = 3000, .description = "wall density"},
           &P::density_kg_per_m3)
      .Add({.name = "mass_scale",
            .unit = "1",
            .min = 0,
            .max = 1e7,
            .description =
                "node mass = density x volume x this (0: automatic, stable explicit meshless step x2 margin)"},
           &P::mass_scale)
      .Add({.name = "support_radius_factor",
            .unit = "1",
            .min = 1.5,
            .max = 4,
            .description = "meshless support radius h in node spacings"},
           &P::support_radius_factor)
      .Add({.name = "substeps", .unit = "count", .min = 1, .max = 16, .description = "physics steps per tick"},
           &P::substeps)
      .Add({.name = "xpbd_iterations",
            .unit = "count",
            .min = 1,
            .max = 50,
            .description = "constraint sweeps per physics step"},
           &P::xpbd_iterations)
      .Add({.name = "stretch_fraction",
            .unit = "1",
            .min = 0,
            .max = 10,
            .description = "stretching-constraint stiffness as a fraction of E x spacing (0: none)"},
           &P::stretch_fraction)
      .Add({.name = "tet_fraction",
            .unit = "1",
            .min = 0,
            .max = 10,
            .description = "tetrahedron energy-constraint spring stiffness as a fraction of E x spacing (0: off)"},
           &P::tet_fraction)
      .Add({.name = "pbd_stiffness",
            .unit = "1",
            .min = 0,
            .max = 1,
            .min_open = true,
            .description = "plain-PBD baseline: each projection moves this fraction of the way (paper's k)"},
           &P::pbd_stiffness)
      .Add({.name = "damping_per_s",
            .unit = "1/s",
            .min = 0,
            .max = 1e4,
            .description = "mass-proportional damping of the wall"},
           &P::damping_per_s)
      .Add({.name = "tissue_modulus_Pa",
            .unit = "Pa",
            .min = 0,
            .max = 1e6,
            .description =
                "E of the tissue around and over the vessel, an elastic foundation on the outer wall (0: none)"},
           &P::tissue_modulus_Pa)
      .Add({.name = "skin",
            .unit = "code",
            .min = -1,
            .max = 1,
            .integer = true,
            .description = "the skin and subcutis the probe indents, in parallel with the vessel (-1: the shape's "
                           "default, on for the straight vein)",
            .choices = {"the shape's default", "off", "on"}},
           &P::skin)
      .Add({.name = "tissue_depth_m",
            .unit = "m",
            .min = 0,
            .max = 0.05,
            .description = "depth over which the foundation's tissue strains (0: the vessel's outer radius)"},
           &P::tissue_depth_m)
      .Add({.name = "lumen_pressure_Pa",
            .unit = "Pa",
            .min = 0,
            .max = 30000,
            .description =
                "blood pressure in the lumen (the wall is inflated to it at build; 6 kPa: a tourniqueted hand vein)"},
           &P::lumen_pressure_Pa)
      .Add({.name = "probe_radius_m",
            .unit = "m",
            .min = 1e-5,
            .max = 0.005,
            .description = "radius of the catheter / probe tip (a sphere)"},
           &P::probe_radius_m)
      .Add({.name = "contact_friction",
            .unit = "1",
            .min = 0,
            .max = 2,
            .description = "Coulomb friction coefficient between probe and tissue"},
           &P::contact_friction)
      .Add({.name = "contact_stiffness_N_per_m",
            .unit = "N/m",
            .min = 1,
            .max = 1e5,
            .description = "tip-node contact stiffness (XPBD compliance = 1 / this)"},
           &P::contact_stiffness_N_per_m)
      .Add({.name = "render_stiffness_max_N_per_m",
            .unit = "N/m",
            .min = 1,
            .max = 1e5,
            .description = "cap on the contact stiffness sent to the device"},
           &P::render_stiffness_max_N_per_m)
      .Add({.name = "max_kinetic_energy_J",
            .unit = "J",
            .min = 0,
            .max = 1e6,
            .min_open = true,
            .description = "a step above this kinetic energy is a blow-up: counted, and the scene resets"},
           &P::max_kinetic_energy_J)
      .Add({.name = "rest_speed_m_per_s",
            .unit = "m/s",
            .min = 0,
            .max = 1e-5,
            .description = "the wall sleeps (its step skipped) once every node is slower than this and the tip still "
                           "or out of reach; 0 = the full step every tick (error vs the full step measured up to 1e-5)"},
           &P::rest_speed_m_per_s);
  return t;
}

double Or(double value, double fallback) { return value > 0.0 ? value : fallback; }

}  // namespace

const ParamTable<VesselParams>& VesselParamTable() {
  static const ParamTable<VesselParams> table = MakeVesselTable();
  return table;
}

VesselGeometryDef VesselGeometryFor(const VesselParams& p) {
  VesselGeometryDef d;
  d.shape = static_cast<VesselShape>(p.shape);
  switch (d.shape) {
    case VesselShape::kStraight:  // hand dorsal vein
      d.length_m = 0.03, d.lumen_radius_m = 1.25e-3, d.wall_thickness_m = 4e-4, d.node_spacing_m = 5e-4;
      break;
    case VesselShape::kBent:  // aortic arch
      d.length_m = 0.134, d.lumen_radius_m = 12.5e-3, d.wall_thickness_m = 2e-3, d.node_spacing_m = 3.2e-3;
      d.bend_radius_m = 0.03, d.bend_angle_rad = std::numbers::pi;
      break;
    case VesselShape::kTwiceBent:  // retinal arteriole
      d.length_m = 3e-3, d.lumen_radius_m = 60e-6, d.wall_thickness_m = 20e-6, d.node_spacing_m = 35e-6;
      d.bend_radius_m = 0.5e-3, d.bend_angle_rad = std::numbers::pi / 3;
      break;
  }
  d.length_m = Or(p.length_m, d.length_m);
  d.lumen_radius_m = Or(p.lumen_radius_m, d.lumen_radius_m);
  d.wall_thickness_m = Or(p.wall_thickness_m, d.wall_thickness_m);
  d.node_spacing_m = Or(p.node_spacing_m, d.node_spacing_m);
  d.radial_layers = p.radial_layers;
  return d;
}

VesselParams ParseVesselParams(const std::map<std::string, double>& params) {
  const VesselParams p = VesselParamTable().Parse(params);
  const VesselGeometryDef d = VesselGeometryFor(p);
  const double stations = std::max(2.0, std::round(d.length_m / d.node_spacing_m) + 1);
  const double ring =
      std::max(6.0, std::round(2.0 * std::numbers::pi * (d.lumen_radius_m + 0.5 * d.wall_thickness_m) / d.node_spacing_m));
  const double nodes = stations * ring * d.radial_layers;
  if (nodes > VesselLimits::kMaxNodes) {
    std::ostringstream msg;
    msg << "vessel: parameters 'length_m', 'lumen_radius_m', 'wall_thickness_m', 'node_spacing_m' and "
           "'radial_layers' give "
        << nodes << " meshless nodes; the limit is " << VesselLimits::kMaxNodes
        << " (a larger node spacing or a shorter vessel)";
    throw std::invalid_argument(msg.str());
  }
  return p;
}

}  // namespace hapsim::core
