#include "hapsim/core/needle/hex_net_topology.h"

#include <cmath>
#include <cstdint>
#include <map>
#include <stdexcept>
#include <utility>
#include <vector>

namespace hapsim::core {

namespace {

// Axial lattice coordinates (q, r); the six neighbour directions in order,
// so walking them d steps each traces ring d.
constexpr int kHexNetDirections[6][2] = {{1, 0}, {0, 1}, {-1, 1}, {-1, 0}, {0, -1}, {1, -1}};

using HexNetCoordinates = std::vector<std::pair<int, int>>;
using HexNetIndex = std::map<std::pair<int, int>, std::int32_t>;

// MakeHexNetTopology's steps, in order.

// Every node's lattice coordinates, ring by ring (N1 first); fills the
// ring bookkeeping (ring_of_node, ring_first_node).
HexNetCoordinates WalkHexNetRings(HexNetTopology& t) {
  HexNetCoordinates qr;
  for (int j = 1; j <= t.rings_w; ++j) {
    t.ring_first_node.push_back(static_cast<std::int32_t>(qr.size()));
    const int d = j - 1;
    if (d == 0) {
      qr.emplace_back(0, 0);
      continue;
    }
    int q = kHexNetDirections[4][0] * d, r = kHexNetDirections[4][1] * d;  // start at (0, -d)
    for (int side = 0; side < 6; ++side)
      for (int s = 0; s < d; ++s) {
        qr.emplace_back(q, r);
        q += kHexNetDirections[side][0];
        r += kHexNetDirections[side][1];
      }
    for (int k = 0; k < 6 * d; ++k) t.ring_of_node.push_back(j);
  }
  t.ring_of_node.insert(t.ring_of_node.begin(), 1);  // N1
  t.ring_first_node.push_back(static_cast<std::int32_t>(qr.size()));
  return qr;
}

// In-plane offsets from N1 (offset_T_m); returns the node at each lattice
// coordinate.
HexNetIndex PlaceHexNetNodes(const HexNetCoordinates& qr, HexNetTopology& t) {
  const auto n = static_cast<Eigen::Index>(qr.size());
  t.offset_T_m.resize(2, n);
  HexNetIndex index;
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto [q, r] = qr[static_cast<std::size_t>(i)];
    t.offset_T_m.col(i) << t.spacing_L_m * (q + 0.5 * r), t.spacing_L_m * (std::sqrt(3.0) / 2.0) * r;
    index[qr[static_cast<std::size_t>(i)]] = static_cast<std::int32_t>(i);
  }
  return index;
}

// Springs between lattice neighbours and the lattice triangles.
void ConnectHexNetNodes(const HexNetCoordinates& qr, const HexNetIndex& index, HexNetTopology& t) {
  auto find = [&](int q, int r) {
    const auto it = index.find({q, r});
    return it == index.end() ? -1 : it->second;
  };
  for (std::size_t i = 0; i < qr.size(); ++i) {
    const auto [q, r] = qr[i];
    const auto a = static_cast<std::int32_t>(i);
    // Each spring once: three "forward" directions; each triangle once: two.
    for (int k = 0; k < 3; ++k) {
      const std::int32_t b = find(q + kHexNetDirections[k][0], r + kHexNetDirections[k][1]);
      if (b >= 0) t.springs.push_back({a, b});
    }
    for (int k = 0; k < 2; ++k) {
      const std::int32_t b = find(q + kHexNetDirections[k][0], r + kHexNetDirections[k][1]);
      const std::int32_t c = find(q + kHexNetDirections[k + 1][0], r + kHexNetDirections[k + 1][1]);
      if (b >= 0 && c >= 0) t.triangles.push_back({a, b, c});
    }
  }
}

}  // namespace

HexNetTopology MakeHexNetTopology(int rings_w, double spacing_L_m) {
  if (rings_w < 1) throw std::invalid_argument("force net: rings w must be >= 1");
  if (!(spacing_L_m > 0.0) || !std::isfinite(spacing_L_m))
    throw std::invalid_argument("force net: spring length L must be > 0");
  HexNetTopology t;
  t.rings_w = rings_w;
  t.spacing_L_m = spacing_L_m;
  const HexNetCoordinates qr = WalkHexNetRings(t);
  const HexNetIndex index = PlaceHexNetNodes(qr, t);
  ConnectHexNetNodes(qr, index, t);
  return t;
}

}  // namespace hapsim::core
