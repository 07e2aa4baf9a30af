#include "hapsim/core/cutting/skin_mesh.h"

#include <cmath>
#include <stdexcept>

#include <Eigen/Geometry>

namespace hapsim::core {

namespace {

double RestArea(const SkinMesh& s, std::uint32_t t) {
  const auto& v = s.topology.TriangleVertices(t);
  const Eigen::Vector3d a = s.model.x0_m.col(v[0]), b = s.model.x0_m.col(v[1]), c = s.model.x0_m.col(v[2]);
  return 0.5 * (b - a).cross(c - a).z();
}

void CheckSkinDef(const SkinDef& d) {
  if (!(d.spacing_m > 0.0 && d.length_m >= 2 * d.spacing_m && d.width_m >= 2 * d.spacing_m))
    throw std::invalid_argument("skin patch: spacing_m must be > 0 and at most half the patch length and width");
  if (!(d.areal_density_kg_per_m2 > 0.0)) throw std::invalid_argument("skin patch: areal density must be > 0");
  if (!(d.prestrain >= 0.0 && d.prestrain < 0.5))
    throw std::invalid_argument("skin patch: prestrain must be in [0, 0.5)");
}

int SkinNode(const SkinMesh& s, int i, int j) { return j * s.nx + i; }

// The lattice as a mass-spring definition: grid edges, both cell diagonals,
// two-apart bending springs, and every node anchored where it lies; with
// room for what cuts add.
MsmDef SkinLatticeDef(const SkinDef& d, const SkinMesh& s) {
  const int n = s.nx * s.ny;
  const double hx = d.length_m / (s.nx - 1), hy = d.width_m / (s.ny - 1);
  auto node = [&](int i, int j) { return SkinNode(s, i, j); };
  MsmDef m;
  m.x0_m.resize(3, n);
  for (int j = 0; j < s.ny; ++j)
    for (int i = 0; i < s.nx; ++i) m.x0_m.col(node(i, j)) << -0.5 * d.length_m + i * hx, -0.5 * d.width_m + j * hy, 0.0;
  m.mass_kg = Eigen::VectorXd::Constant(n, 1.0);  // re-lumped from the triangles once they exist
  m.node_damping_Ns_per_m = Eigen::VectorXd::Constant(n, d.node_damping_Ns_per_m);
  auto spring = [&](int a, int b, double k) {
    m.springs.push_back({a, b});
    m.spring_rest_m.push_back((m.x0_m.col(a) - m.x0_m.col(b)).norm() * (1.0 - d.prestrain));
    m.spring_k_N_per_m.push_back(k);
    m.spring_c_Ns_per_m.push_back(d.spring_c_Ns_per_m);
  };
  for (int j = 0; j < s.ny; ++j)
    for (int i = 0; i < s.nx; ++i) {
      if (i + 1 < s.nx) spring(node(i, j), node(i + 1, j), d.spring_k_N_per_m);
      if (j + 1 < s.ny) spring(node(i, j), node(i, j + 1), d.spring_k_N_per_m);
      if (i + 1 < s.nx && j + 1 < s.ny) {
        spring(node(i, j), node(i + 1, j + 1), d.spring_k_N_per_m);
        spring(node(i + 1, j), node(i, j + 1), d.spring_k_N_per_m);
      }
      if (i + 2 < s.nx) spring(node(i, j), node(i + 2, j), d.bending_k_N_per_m);
      if (j + 2 < s.ny) spring(node(i, j), node(i, j + 2), d.bending_k_N_per_m);
    }
  for (int v = 0; v < n; ++v) {
    m.anchor_node.push_back(v);
    m.anchor_k_N_per_m.push_back(d.anchor_k_N_per_m);
  }
  m.anchor_point_W_m = m.x0_m;
  m.spring_capacity = static_cast<std::int32_t>(m.springs.size() + d.extra_springs);
  m.node_capacity = n + static_cast<std::int32_t>(d.extra_vertices);
  m.max_node_degree = d.max_node_degree;
  return m;
}

// The displayed mesh: one vertex slot per node, two triangles per cell,
// with room for what cuts add.
void BuildSkinTopology(const SkinDef& d, SkinMesh& s) {
  std::vector<std::string> parts = {"skin", "wound"};
  parts.insert(parts.end(), d.extra_parts.begin(), d.extra_parts.end());
  s.topology =
      MeshTopology({.vertex_capacity = static_cast<std::uint32_t>(s.model.num_nodes),
                    .triangle_capacity = static_cast<std::uint32_t>(2 * (s.nx - 1) * (s.ny - 1)) + d.extra_triangles,
                    .part_names = parts,
                    .log_capacity = 8192,
                    .max_vertex_triangles = d.max_vertex_triangles});
  for (int v = 0; v < s.nx * s.ny; ++v) s.topology.AddVertex();
  for (int j = 0; j + 1 < s.ny; ++j)
    for (int i = 0; i + 1 < s.nx; ++i) {
      const auto a = static_cast<std::uint32_t>(SkinNode(s, i, j)),
                 b = static_cast<std::uint32_t>(SkinNode(s, i + 1, j)),
                 c = static_cast<std::uint32_t>(SkinNode(s, i + 1, j + 1)),
                 e = static_cast<std::uint32_t>(SkinNode(s, i, j + 1));
      s.topology.AddTriangle(a, b, c, kSkinPart);  // counter-clockwise seen from +z
      s.topology.AddTriangle(a, c, e, kSkinPart);
    }
  s.topology.Seal();
}

}  // namespace

SkinMesh BuildSkinMesh(const SkinDef& d) {
  CheckSkinDef(d);
  SkinMesh s;
  s.def = d;
  s.nx = static_cast<int>(std::lround(d.length_m / d.spacing_m)) + 1;
  s.ny = static_cast<int>(std::lround(d.width_m / d.spacing_m)) + 1;
  s.model = BuildMsmModel(SkinLatticeDef(d, s));
  s.state = MakeMsmState(s.model);
  BuildSkinTopology(d, s);
  const auto vcap = static_cast<std::uint32_t>(s.model.num_nodes);
  s.on_border.assign(vcap, 0);
  s.on_lip.assign(vcap, 0);
  for (int j = 0; j < s.ny; ++j)
    for (int i = 0; i < s.nx; ++i)
      s.on_border[static_cast<std::size_t>(SkinNode(s, i, j))] = (i == 0 || j == 0 || i == s.nx - 1 || j == s.ny - 1);
  s.lip_nodes.reserve(vcap);
  s.wound_edges.reserve(static_cast<std::size_t>(vcap) * 2);
  // Masses from the triangles' rest areas (density x area / 3 per corner).
  for (int v = 0; v < s.nx * s.ny; ++v) RelumpNodeMass(s, static_cast<std::uint32_t>(v));
  s.hold_N = Eigen::Matrix3Xd::Zero(3, s.model.num_nodes);
  UpdatePrestressHold(s);
  return s;
}

namespace {

// A spring's pull on its node a (towards b) with both at rest.
Eigen::Vector3d RestPullOnA(const MsmModel& m, std::size_t spring) {
  const Eigen::Vector3d d = m.x0_m.col(m.spring_j[spring]) - m.x0_m.col(m.spring_i[spring]);
  const double length = d.norm();
  return (m.spring_k_N_per_m[spring] * (length - m.spring_rest_m[spring]) / length) * d;
}

}  // namespace

void UpdatePrestressHoldOf(SkinMesh& s, std::uint32_t v) {
  s.hold_N.col(v).setZero();
  if (s.def.prestrain == 0.0) return;
  const auto node = static_cast<std::int32_t>(v);
  for (std::int32_t e = 0; e < s.model.DegreeOf(node); ++e) {
    const auto k = static_cast<std::size_t>(s.model.SpringsOf(node)[e]);
    const Eigen::Vector3d pull = RestPullOnA(s.model, k);
    s.hold_N.col(v) -= s.model.spring_i[k] == node ? pull : Eigen::Vector3d(-pull);
  }
}

void UpdatePrestressHold(SkinMesh& s) {
  s.hold_N.setZero();
  if (s.def.prestrain == 0.0) return;  // springs at rest length at rest pull nothing
  const MsmModel& m = s.model;
  for (std::int32_t k = 0; k < m.NumSprings(); ++k) {
    const auto i = static_cast<std::size_t>(k);
    const Eigen::Vector3d pull = RestPullOnA(m, i);
    s.hold_N.col(m.spring_i[i]) -= pull;
    s.hold_N.col(m.spring_j[i]) += pull;
  }
}

void RelumpNodeMass(SkinMesh& s, std::uint32_t v) {
  double area = 0.0;
  for (const std::uint32_t t : s.topology.TrianglesOf(v)) area += RestArea(s, t);
  double m = s.def.areal_density_kg_per_m2 * area / 3.0;
  if (m < s.def.min_node_mass_kg) {
    m = s.def.min_node_mass_kg;
    ++s.mass_floor_hits;
  }
  const auto i = static_cast<Eigen::Index>(v);
  s.model.mass_kg[i] = m;
  if (!s.model.fixed[v]) s.model.inv_mass_free_per_kg[i] = 1.0 / m;
}

double TotalNodeMass_kg(const SkinMesh& s) {
  double m = 0.0;
  for (std::int32_t v = 0; v < s.model.num_nodes; ++v)
    if (s.model.node_live[static_cast<std::size_t>(v)]) m += s.model.mass_kg[v];  // skin nodes only (not a tool's slots)
  return m;
}

double LiveRestArea_m2(const SkinMesh& s) {
  double a = 0.0;
  for (std::uint32_t t = 0; t < s.topology.Triangles().HighWater(); ++t)
    if (s.topology.Triangles().IsLive(t) && s.topology.TrianglePart(t) <= kWoundPart) a += RestArea(s, t);
  return a;
}

void ApplyResidualStress(SkinMesh& s, double sigma_r_Pa, double thickness_m) {
  for (const std::uint32_t v : s.lip_nodes) s.state.f_residual_N.col(v).setZero();
  const double traction_N_per_m = sigma_r_Pa * thickness_m;
  for (const auto& [a, b] : s.wound_edges) {
    // The face's area from the rest length (small strain: a face stretched
    // by the motion must not pull harder, or a loose node would run away);
    // its direction from the current edge: left of a -> b, z x e.
    const double rest_m = (s.model.x0_m.col(b) - s.model.x0_m.col(a)).norm();
    const Eigen::Vector3d e = s.state.x_m.col(b) - s.state.x_m.col(a);
    const Eigen::Vector3d left(-e.y(), e.x(), 0.0);
    const double l = left.norm();
    if (!(l > 0.0)) continue;
    const Eigen::Vector3d half = (0.5 * traction_N_per_m * rest_m / l) * left;  // sigma_r t l0 / 2 along the unit normal
    s.state.f_residual_N.col(a) += half;
    s.state.f_residual_N.col(b) += half;
  }
}

}  // namespace hapsim::core
