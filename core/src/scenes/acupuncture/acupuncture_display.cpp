// acupuncture scene display: layer patches displaced radially by their force
// nets, and the needle mesh following the tool.
#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "hapsim/core/math/portable_math.h"
#include "hapsim/core/scenes/acupuncture/acupuncture_scene.h"

namespace hapsim::core {

namespace {
constexpr int kNeedleSides = 6;
constexpr int kNeedleVertices = 1 + 2 * kNeedleSides;
constexpr double kNeedleTaper_m = 0.6e-3;  // length of the conical point

// BuildDisplay's steps.

// Vertex slots: the three patches (layer by layer), then the needle; parts
// are the layer names and "needle". Topology never changes.
MeshTopology MakeAcupunctureTopology(const AcupunctureParams& params, int total_patch) {
  const int g = params.patch_grid_nodes;
  std::vector<std::string> part_names;
  for (const auto& l : params.layers) part_names.push_back(l.name);
  part_names.push_back("needle");
  const auto patch_triangles = static_cast<std::uint32_t>(2 * (g - 1) * (g - 1));
  MeshTopology topology({.vertex_capacity = static_cast<std::uint32_t>(total_patch + kNeedleVertices),
                         .triangle_capacity = kNumTissueLayers * patch_triangles + 4 * kNeedleSides - 2,
                         .part_names = part_names,
                         .log_capacity = 0});
  for (int v = 0; v < total_patch + kNeedleVertices; ++v) topology.AddVertex();
  return topology;
}

// Two triangles per cell of a g x g patch whose slots start at base.
void AddAcupuncturePatchTriangles(int base, int g, std::uint16_t part, MeshTopology& topology) {
  for (int iy = 0; iy + 1 < g; ++iy)
    for (int ix = 0; ix + 1 < g; ++ix) {
      const auto v00 = static_cast<std::uint32_t>(base + ix + g * iy);
      const auto v10 = v00 + 1, v01 = v00 + static_cast<std::uint32_t>(g), v11 = v01 + 1;
      topology.AddTriangle(v00, v10, v11, part);  // outward (+z) winding
      topology.AddTriangle(v00, v11, v01, part);
    }
}

// Needle: point, a ring where the taper ends, a ring at the back, a cap;
// its slots start at tip.
void AddAcupunctureNeedleTriangles(std::uint32_t tip, std::uint16_t part, MeshTopology& topology) {
  for (std::uint32_t k = 0; k < kNeedleSides; ++k) {
    const std::uint32_t a0 = tip + 1 + k, a1 = tip + 1 + (k + 1) % kNeedleSides;
    const std::uint32_t b0 = a0 + kNeedleSides, b1 = a1 + kNeedleSides;
    topology.AddTriangle(tip, a1, a0, part);
    topology.AddTriangle(a0, a1, b1, part);
    topology.AddTriangle(a0, b1, b0, part);
  }
  for (std::uint32_t k = 1; k + 1 < kNeedleSides; ++k)
    topology.AddTriangle(tip + 1 + kNeedleSides, tip + 1 + kNeedleSides + k, tip + 2 + kNeedleSides + k, part);
}

}  // namespace

void AcupunctureScene::BuildDisplay() {
  const int g = params_.patch_grid_nodes;
  patch_vertices_ = g * g;
  const int total_patch = kNumTissueLayers * patch_vertices_;
  topology_ = MakeAcupunctureTopology(params_, total_patch);
  patch_rest_W_m_.resize(3, total_patch);
  patch_dir_W_.resize(3, total_patch);
  for (int layer = 0; layer < kNumTissueLayers; ++layer) {
    PlacePatchVertices(layer);
    AddAcupuncturePatchTriangles(layer * patch_vertices_, g, static_cast<std::uint16_t>(layer), topology_);
  }
  AddAcupunctureNeedleTriangles(static_cast<std::uint32_t>(total_patch), static_cast<std::uint16_t>(kNumTissueLayers),
                                topology_);
  topology_.Seal();
  for (auto& near : patch_near_net_) near.reserve(static_cast<std::size_t>(patch_vertices_));
  for (auto& q : patch_near_q_) q.reserve(static_cast<std::size_t>(patch_vertices_));
  vertices_m_.resize(3, total_patch + kNeedleVertices);
  vertices_m_.leftCols(total_patch) = patch_rest_W_m_;  // the needle is placed by ResetState()
}

// A layer's patch at rest: a square grid in the xy-plane around the site,
// projected radially onto the layer's surface.
void AcupunctureScene::PlacePatchVertices(int layer) {
  const int g = params_.patch_grid_nodes;
  const int base = layer * patch_vertices_;
  const Eigen::Vector3d c = body_.Def().center_W_m;
  for (int iy = 0; iy < g; ++iy)
    for (int ix = 0; ix < g; ++ix) {
      const double x = params_.patch_size_m * (static_cast<double>(ix) / (g - 1) - 0.5);
      const double y = params_.patch_size_m * (static_cast<double>(iy) / (g - 1) - 0.5);
      const Eigen::Vector3d dir = (Eigen::Vector3d(x, y, 0.0) - c).normalized();
      patch_rest_W_m_.col(base + ix + g * iy) = body_.SurfacePoint_W_m(layer, dir);
      patch_dir_W_.col(base + ix + g * iy) = dir;
    }
}

void AcupunctureScene::ShowNet(int layer) {
  const auto i = static_cast<std::size_t>(layer);
  const ForceNetState& s = net_states_[i];
  const double inv_L = 1.0 / nets_[i].def.spacing_L_m;
  const double reach_q = nets_[i].def.rings_w;  // ring w plus the one-spacing taper
  const int base = layer * patch_vertices_;
  patch_near_net_[i].clear();  // capacity G² reserved at build: no allocation
  patch_near_q_[i].clear();
  for (int k = 0; k < patch_vertices_; ++k) {
    const Eigen::Vector3d d = patch_rest_W_m_.col(base + k) - s.n1_rest_W_m;
    const double q = (d - d.dot(s.normal_W) * s.normal_W).norm() * inv_L;
    if (q < reach_q) {
      patch_near_net_[i].push_back(base + k);
      patch_near_q_[i].push_back(q);
    }
  }
  net_shown_[i] = true;
  net_moved_[i] = true;
}

void AcupunctureScene::HideNet(int layer) {
  const auto i = static_cast<std::size_t>(layer);
  for (const std::int32_t v : patch_near_net_[i]) vertices_m_.col(v) = patch_rest_W_m_.col(v);
  patch_near_net_[i].clear();
  patch_near_q_[i].clear();
  net_shown_[i] = false;
  net_moved_[i] = false;
}

void AcupunctureScene::UpdatePatches() {
  for (std::size_t i = 0; i < kNumTissueLayers; ++i) {
    if (!net_shown_[i] || !net_moved_[i]) continue;
    net_moved_[i] = false;
    // Radial displacement of the SH surface by the ring profile Z_j at the
    // vertex's in-plane distance from N1 (linear between rings, tapering to
    // zero one spacing beyond ring w).
    const Eigen::VectorXd& ring_Z_m = net_states_[i].ring_Z_m;
    const int w = nets_[i].def.rings_w;
    for (std::size_t n = 0; n < patch_near_net_[i].size(); ++n) {
      const std::int32_t v = patch_near_net_[i][n];
      const double q = patch_near_q_[i][n];
      double z_m = 0.0;
      if (q < w - 1) {
        const int j = static_cast<int>(q);
        z_m = ring_Z_m[j] + (q - j) * (ring_Z_m[j + 1] - ring_Z_m[j]);
      } else if (q < w) {
        z_m = ring_Z_m[w - 1] * (w - q);
      }
      vertices_m_.col(v) = patch_rest_W_m_.col(v) - z_m * patch_dir_W_.col(v);
    }
  }
}

void AcupunctureScene::UpdateNeedleMesh(const Eigen::Vector3d& tip, const Eigen::Vector3d& axis) {
  const int base = kNumTissueLayers * patch_vertices_;
  const Eigen::Vector3d t1 = axis.unitOrthogonal(), t2 = axis.cross(t1);
  vertices_m_.col(base) = tip;
  for (int k = 0; k < kNeedleSides; ++k) {
    const double ang = 2.0 * 3.14159265358979323846 * k / kNeedleSides;
    const Eigen::Vector3d rim = params_.needle_radius_m * (pmath::Cos(ang) * t1 + pmath::Sin(ang) * t2);
    vertices_m_.col(base + 1 + k) = tip - kNeedleTaper_m * axis + rim;
    vertices_m_.col(base + 1 + kNeedleSides + k) = tip - params_.needle_length_m * axis + rim;
  }
}

}  // namespace hapsim::core
