// Vessel generators for the vascular scene (the vascular paper's
// straight, bent and twice-bent vessels): a tube wall along a centreline in
// the horizontal plane, sampled as meshless nodes on `radial_layers` rings
// from the lumen to the outer radius, and a display surface (outer wall and
// lumen, closed by end rings) for the MLS map. The tube lies with its top at
// z = 0 (the tool comes from +z); the centreline's bounding box is centred on
// the origin. Both end stations are anchored (the vessel held where it
// leaves the field).
//
// Node volumes partition the wall exactly: each node owns its share of the
// annulus between the mid-radii to its neighbouring layers and half-way to
// its neighbouring stations, so the volumes add up to centreline length x
// pi (r_out^2 - r_in^2) — for a bent tube too (Pappus), while the centreline
// bends no tighter than its outer radius.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace hapsim::core {

enum class VesselShape : int { kStraight = 0, kBent = 1, kTwiceBent = 2 };

struct VesselGeometryDef {
  VesselShape shape = VesselShape::kStraight;
  double length_m = 0.03;           // centreline length
  double lumen_radius_m = 1.25e-3;  // r_in
  double wall_thickness_m = 4e-4;   // r_out = r_in + thickness
  double bend_radius_m = 0.0;       // centreline radius of each bend (kBent, kTwiceBent)
  double bend_angle_rad = 0.0;      // each bend's turn; kTwiceBent turns back by the same angle
  double node_spacing_m = 5e-4;     // target axial and circumferential spacing
  int radial_layers = 2;            // rings across the wall, lumen to outer surface (>= 2)
};

struct VesselGeometry {
  Eigen::Matrix3Xd nodes_m;             // (3 x nodes): station-major, then layer, then angle
  std::vector<double> node_volume_m3;   // (nodes)
  std::vector<std::uint8_t> anchored;   // (nodes) 1 at both end stations
  int stations = 0, layers = 0, ring = 0;  // nodes per station = layers x ring
  Eigen::Matrix3Xd surface_m;           // (3 x vertices): outer rings, then lumen rings
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<std::uint16_t> triangle_part;  // 0: outer wall, 1: lumen
  Eigen::Matrix3Xd centreline_m;        // (3 x stations) centreline at each station
  double centreline_length_m = 0.0;
  double outer_radius_m = 0.0;
};

// Throws std::invalid_argument naming the bad field: non-positive sizes, fewer
// than 2 layers, a bend tighter than the outer radius, or more than 200 000
// nodes.
VesselGeometry GenerateVessel(const VesselGeometryDef& def);

}  // namespace hapsim::core
