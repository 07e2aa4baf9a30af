// The 50k-vertex mesh of tests/bench/viewer_render.cpp (Sheet(224)), as the
// viewer holds it after MeshCache::Apply + LiveScene::OnFrame: positions are
// quantised to 1e-5 m (lround(v / 1e-5)) then float(q * 1e-5); triangles as
// listed, all part 0. `dent` lets the caller move the tool's dent (the
// deformation that follows a keyframe): depth_m, centre (cx, cy), width2 (the
// 1e-4 of exp(-r^2 / 1e-4)).
#pragma once
#include <cmath>
#include <cstdint>
#include <vector>

struct Dent {
  double depth_m = 0.003, cx = 0.0, cy = 0.0, width2 = 1e-4;
};

struct SheetMesh {
  std::vector<float> positions_m;
  std::vector<std::uint32_t> triangles;
  std::vector<std::uint16_t> parts;
};

inline std::vector<float> SheetPositions(int n, const std::vector<Dent>& dents) {
  std::vector<float> p;
  p.reserve(3 * static_cast<std::size_t>(n) * n);
  const double quantum = 1e-5;
  for (int iy = 0; iy < n; ++iy)
    for (int ix = 0; ix < n; ++ix) {
      const double x = 0.06 * (ix / (n - 1.0) - 0.5), y = 0.06 * (iy / (n - 1.0) - 0.5);
      double z = 0.0;
      for (const Dent& d : dents) {
        const double dx = x - d.cx, dy = y - d.cy;
        z += -d.depth_m * std::exp(-(dx * dx + dy * dy) / d.width2);
      }
      for (const double v : {x, y, z}) {
        const auto q = static_cast<std::int32_t>(std::lround(v / quantum));
        p.push_back(static_cast<float>(q * quantum));
      }
    }
  return p;
}

inline SheetMesh Sheet(int n, const std::vector<Dent>& dents = {Dent{}}) {
  SheetMesh s;
  s.positions_m = SheetPositions(n, dents);
  for (int iy = 0; iy + 1 < n; ++iy)
    for (int ix = 0; ix + 1 < n; ++ix) {
      const auto v = static_cast<std::uint32_t>(ix + n * iy), nu = static_cast<std::uint32_t>(n);
      for (const std::uint32_t t : {v, v + 1, v + nu + 1, v, v + nu + 1, v + nu}) s.triangles.push_back(t);
      s.parts.push_back(0);
      s.parts.push_back(0);
    }
  return s;
}
