// Topology of the acupuncture paper's mass-spring force net (§3.2, Fig. 1):
// concentric hexagonal rings around the contact point N1 on a triangular
// lattice. Ring j (1-based) holds 6(j-1) particles (ring 1 = N1 alone), w
// rings hold 1 + 3w(w-1); adjacent particles are a spring length L apart.
// Nodes are numbered ring by ring (node 0 = N1), so per-ring quantities are
// contiguous runs.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace hapsim::core {

struct HexNetTopology {
  int rings_w = 0;
  double spacing_L_m = 0.0;
  Eigen::Matrix2Xd offset_T_m;                        // in-plane offsets from N1 (2 x n)
  std::vector<std::int32_t> ring_of_node;             // 1-based ring j per node (n)
  std::vector<std::int32_t> ring_first_node;          // first node of ring j-1, plus n at the end (w + 1)
  std::vector<std::array<std::int32_t, 2>> springs;   // lattice neighbours at distance L
  std::vector<std::array<std::int32_t, 3>> triangles; // lattice triangles (display, checks)

  std::int32_t NumNodes() const { return static_cast<std::int32_t>(ring_of_node.size()); }
};

// Throws std::invalid_argument unless rings_w >= 1 and spacing_L_m > 0.
HexNetTopology MakeHexNetTopology(int rings_w, double spacing_L_m);

}  // namespace hapsim::core
