#include "hapsim/core/scenes/vessel/vessel_geometry.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "hapsim/core/math/portable_math.h"

namespace hapsim::core {
namespace {


// The centreline as segments in the horizontal plane: straight runs and arcs
// (signed turn). Sampled by arc length.
struct Segment {
  double length_m;
  double turn_rad;  // 0: straight
};

std::vector<Segment> Centreline(const VesselGeometryDef& d) {
  const double arc = d.bend_radius_m * std::abs(d.bend_angle_rad);
  switch (d.shape) {
    case VesselShape::kStraight: return {{d.length_m, 0.0}};
    case VesselShape::kBent: {
      const double run = 0.5 * (d.length_m - arc);
      return {{run, 0.0}, {arc, d.bend_angle_rad}, {run, 0.0}};
    }
    case VesselShape::kTwiceBent: {
      const double run = (d.length_m - 2.0 * arc) / 3.0;
      return {{run, 0.0}, {arc, d.bend_angle_rad}, {run, 0.0}, {arc, -d.bend_angle_rad}, {run, 0.0}};
    }
  }
  return {};
}

// Position and unit tangent at arc length s (heading 0 = +x at s = 0).
void Sample(const std::vector<Segment>& segments, double s, Eigen::Vector2d* p, Eigen::Vector2d* t) {
  Eigen::Vector2d pos(0, 0);
  double heading = 0.0;
  for (const Segment& g : segments) {
    const double ds = std::min(s, g.length_m);
    if (g.turn_rad == 0.0 || g.length_m == 0.0) {
      pos += ds * Eigen::Vector2d(pmath::Cos(heading), pmath::Sin(heading));
    } else {
      const double curvature = g.turn_rad / g.length_m;  // signed 1/R
      const double h1 = heading + curvature * ds;
      pos += Eigen::Vector2d(pmath::Sin(h1) - pmath::Sin(heading), pmath::Cos(heading) - pmath::Cos(h1)) / curvature;
      heading = h1;
      if (s <= g.length_m) break;
      s -= g.length_m;
      continue;
    }
    if (s <= g.length_m) break;
    s -= g.length_m;
  }
  *p = pos;
  *t = Eigen::Vector2d(pmath::Cos(heading), pmath::Sin(heading));
}

void Check(const VesselGeometryDef& d) {
  auto positive = [](double v, const char* name) {
    if (!(v > 0.0) || !std::isfinite(v)) throw std::invalid_argument(std::string("vessel: ") + name + " must be > 0");
  };
  positive(d.length_m, "length");
  positive(d.lumen_radius_m, "lumen radius");
  positive(d.wall_thickness_m, "wall thickness");
  positive(d.node_spacing_m, "node spacing");
  if (d.radial_layers < 2 || d.radial_layers > 16) throw std::invalid_argument("vessel: radial layers must be in [2, 16]");
  if (d.shape != VesselShape::kStraight) {
    positive(d.bend_radius_m, "bend radius");
    if (!(std::abs(d.bend_angle_rad) > 0.0 && std::abs(d.bend_angle_rad) <= std::numbers::pi)) {
      throw std::invalid_argument("vessel: bend angle must be in (0, pi] rad");
    }
    const double r_out = d.lumen_radius_m + d.wall_thickness_m;
    if (d.bend_radius_m <= r_out) {
      throw std::invalid_argument("vessel: bend radius must exceed the outer radius (the wall would fold)");
    }
    const int bends = d.shape == VesselShape::kBent ? 1 : 2;
    if (bends * d.bend_radius_m * std::abs(d.bend_angle_rad) >= d.length_m) {
      throw std::invalid_argument("vessel: the bends are longer than the vessel (raise length or lower bend radius/angle)");
    }
  }
}

// GenerateVessel's steps, in order.

// The lattice's size: stations along, rings around, layers across.
void SizeVesselLattice(const VesselGeometryDef& d, VesselGeometry& g) {
  const double r_in = d.lumen_radius_m, r_out = r_in + d.wall_thickness_m;
  g.outer_radius_m = r_out;
  g.layers = d.radial_layers;
  g.stations = std::max(2, static_cast<int>(std::lround(d.length_m / d.node_spacing_m)) + 1);
  g.ring = std::max(6, static_cast<int>(std::lround(2.0 * std::numbers::pi * 0.5 * (r_in + r_out) / d.node_spacing_m)));
  const double nodes = static_cast<double>(g.stations) * g.layers * g.ring;
  if (nodes > 200000) {
    throw std::invalid_argument("vessel: " + std::to_string(static_cast<long long>(nodes)) +
                                " nodes (more than 200 000): raise the node spacing");
  }
}

// Centreline samples at the stations, then centred on the origin in x-y; z
// so the top of the tube is at 0. Returns the unit tangent at each station.
std::vector<Eigen::Vector2d> SampleVesselCentreline(const VesselGeometryDef& d, VesselGeometry& g) {
  const std::vector<Segment> segments = Centreline(d);
  g.centreline_length_m = d.length_m;
  std::vector<Eigen::Vector2d> p(static_cast<std::size_t>(g.stations)), t(p.size());
  const double ds = d.length_m / (g.stations - 1);
  for (int k = 0; k < g.stations; ++k) Sample(segments, k * ds, &p[static_cast<std::size_t>(k)], &t[static_cast<std::size_t>(k)]);
  Eigen::Vector2d lo = p[0], hi = p[0];
  for (const auto& q : p) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
  const Eigen::Vector2d centre = 0.5 * (lo + hi);
  g.centreline_m.resize(3, g.stations);
  for (int k = 0; k < g.stations; ++k) {
    g.centreline_m.col(k) << p[static_cast<std::size_t>(k)] - centre, -g.outer_radius_m;
  }
  return t;
}

// A point on the ring of radius r around station k, at angle index a (0:
// straight up, then towards up x tangent).
Eigen::Vector3d VesselRingPoint(const VesselGeometry& g, const std::vector<Eigen::Vector2d>& tangents, int k, double r,
                                int a) {
  const double dphi = 2.0 * std::numbers::pi / g.ring;
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d tangent(tangents[static_cast<std::size_t>(k)].x(), tangents[static_cast<std::size_t>(k)].y(),
                                0.0);
  const Eigen::Vector3d side = up.cross(tangent);
  const double phi = a * dphi;
  return Eigen::Vector3d(g.centreline_m.col(k) + r * (pmath::Cos(phi) * up + pmath::Sin(phi) * side));
}

// The nodes, station by station, layer by layer, around; each owns its
// share of the wall's volume (layer radii and the mid-radii between them).
void PlaceVesselNodes(const VesselGeometryDef& d, const std::vector<Eigen::Vector2d>& tangents, VesselGeometry& g) {
  const double r_in = d.lumen_radius_m, r_out = g.outer_radius_m;
  std::vector<double> radius(static_cast<std::size_t>(g.layers)), lo_r(radius.size()), hi_r(radius.size());
  for (int l = 0; l < g.layers; ++l) radius[static_cast<std::size_t>(l)] = r_in + (r_out - r_in) * l / (g.layers - 1);
  for (int l = 0; l < g.layers; ++l) {
    const auto u = static_cast<std::size_t>(l);
    lo_r[u] = l == 0 ? r_in : 0.5 * (radius[u - 1] + radius[u]);
    hi_r[u] = l == g.layers - 1 ? r_out : 0.5 * (radius[u] + radius[u + 1]);
  }
  const double ds = d.length_m / (g.stations - 1);
  const double dphi = 2.0 * std::numbers::pi / g.ring;
  const auto n = static_cast<Eigen::Index>(static_cast<double>(g.stations) * g.layers * g.ring);
  g.nodes_m.resize(3, n);
  g.node_volume_m3.resize(static_cast<std::size_t>(n));
  g.anchored.assign(static_cast<std::size_t>(n), 0);
  Eigen::Index i = 0;
  for (int k = 0; k < g.stations; ++k) {
    const double axial = (k == 0 || k == g.stations - 1) ? 0.5 * ds : ds;
    for (int l = 0; l < g.layers; ++l) {
      const auto u = static_cast<std::size_t>(l);
      const double volume = axial * 0.5 * dphi * (hi_r[u] * hi_r[u] - lo_r[u] * lo_r[u]);
      for (int a = 0; a < g.ring; ++a, ++i) {
        g.nodes_m.col(i) = VesselRingPoint(g, tangents, k, radius[u], a);
        g.node_volume_m3[static_cast<std::size_t>(i)] = volume;
        g.anchored[static_cast<std::size_t>(i)] = (k == 0 || k == g.stations - 1) ? 1 : 0;
      }
    }
  }
}

// Display surface: outer rings (part 0) then lumen rings (part 1), same
// stations and angles as the nodes; quads split in two, end rings closing
// the wall (part 0). Outward normals by vertex order.
void BuildVesselSurface(const VesselGeometryDef& d, const std::vector<Eigen::Vector2d>& tangents, VesselGeometry& g) {
  const double r_in = d.lumen_radius_m, r_out = g.outer_radius_m;
  const int ring = g.ring, S = g.stations;
  g.surface_m.resize(3, 2 * S * ring);
  for (int k = 0; k < S; ++k)
    for (int a = 0; a < ring; ++a) {
      g.surface_m.col(k * ring + a) = VesselRingPoint(g, tangents, k, r_out, a);
      g.surface_m.col(S * ring + k * ring + a) = VesselRingPoint(g, tangents, k, r_in, a);
    }
  auto vertex = [&](int side, int k, int a) { return static_cast<std::uint32_t>(side * S * ring + k * ring + (a % ring)); };
  auto quad = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t e, std::uint16_t part) {
    g.triangles.push_back({a, b, c});
    g.triangles.push_back({a, c, e});
    g.triangle_part.push_back(part);
    g.triangle_part.push_back(part);
  };
  for (int k = 0; k + 1 < S; ++k)
    for (int a = 0; a < ring; ++a) {
      quad(vertex(0, k, a), vertex(0, k + 1, a), vertex(0, k + 1, a + 1), vertex(0, k, a + 1), 0);
      quad(vertex(1, k, a), vertex(1, k, a + 1), vertex(1, k + 1, a + 1), vertex(1, k + 1, a), 1);
    }
  for (int a = 0; a < ring; ++a) {
    quad(vertex(0, 0, a), vertex(0, 0, a + 1), vertex(1, 0, a + 1), vertex(1, 0, a), 0);
    quad(vertex(0, S - 1, a), vertex(1, S - 1, a), vertex(1, S - 1, a + 1), vertex(0, S - 1, a + 1), 0);
  }
}

}  // namespace

VesselGeometry GenerateVessel(const VesselGeometryDef& d) {
  Check(d);
  VesselGeometry g;
  SizeVesselLattice(d, g);
  const std::vector<Eigen::Vector2d> tangents = SampleVesselCentreline(d, g);
  PlaceVesselNodes(d, tangents, g);
  BuildVesselSurface(d, tangents, g);
  return g;
}

}  // namespace hapsim::core
