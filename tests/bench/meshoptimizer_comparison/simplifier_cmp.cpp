// Side-by-side: hapsim's DisplaySimplifier (SimplifyToBudget, vertex
// clustering) vs libmeshoptimizer 0.18 (meshopt_simplify, meshopt_simplifySloppy)
// on the viewer benchmark's 50k-vertex sheet (tests/bench/viewer_render.cpp,
// Sheet(224): 50 176 vertices, 99 458 triangles; sheet.h rebuilds it as the
// viewer holds it after MeshCache and LiveScene — checked identical once).
// Opt-in: cmake -DHAPSIM_BENCH_MESHOPTIMIZER=ON with libmeshoptimizer-dev
// installed builds build/bin/bench_simplifier_vs_meshoptimizer; run it under
// `taskset -c 1`. What it decided: docs/viewer.md, "Display simplifier".
//
// For each budget (50 000 = RenderOptions{}.max_triangles, 25 000, 10 000):
//  - time per simplification: median of kRuns runs (after 2 warm-ups);
//  - triangles out;
//  - geometric error, symmetric, by sampling: area-weighted random points
//    (+ every used vertex) of the coarse mesh to the full mesh's triangles
//    and of the full mesh to the coarse one; RMS and max, in micrometres and
//    as a fraction of the bounding-box diagonal;
//  - triangle shape: fraction with min angle < 10 deg, triangles whose
//    normal opposes the full mesh's vertex normals (flipped);
// in the viewer's usage: the coarse list is computed ONCE on the positions
// at the keyframe (or cut) and then only the positions move (scenarios
// "moved": coarse list from the rest shape, evaluated on deformed positions).
#include <meshoptimizer.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "hapsim/gui/display_simplifier.h"
#include "sheet.h"

namespace {

using Clock = std::chrono::steady_clock;
constexpr int kRuns = 25;

struct Coarse {
  std::vector<std::uint32_t> vertices;  // 3 per triangle, over the full position array
  std::vector<std::uint16_t> parts;
  std::string note;
};

// ---------------------------------------------------------------- methods

Coarse Ours(const SheetMesh& m, std::size_t budget) {
  hapsim::gui::CoarseTriangles c = hapsim::gui::SimplifyToBudget(m.positions_m, m.triangles, m.parts, budget);
  char note[64];
  std::snprintf(note, sizeof note, "cell %.3f mm", c.cell_m * 1e3);
  return {std::move(c.vertices), std::move(c.parts), note};
}

enum class Mode { kSimplify, kSimplifyThenSloppy, kSloppy };

// What a drop-in would have to do: meshopt knows no parts, so the triangles
// are simplified part by part (a budget share each, proportional to the
// part's triangles; with several parts, LockBorder so that the parts stay
// stitched). The sheet has one part, so this is one call plus copies.
Coarse Meshopt(const SheetMesh& m, std::size_t budget, Mode mode, float target_error) {
  Coarse out;
  const std::size_t count = std::min(m.triangles.size() / 3, m.parts.size());
  if (budget == 0 || count <= budget) {
    out.vertices.assign(m.triangles.begin(), m.triangles.begin() + 3 * count);
    out.parts.assign(m.parts.begin(), m.parts.begin() + count);
    return out;
  }
  const std::uint16_t max_part = *std::max_element(m.parts.begin(), m.parts.begin() + count);
  const std::size_t vertex_count = m.positions_m.size() / 3;
  std::vector<unsigned> in, dst;
  float worst_error = 0.0f;
  bool sloppy_used = false;
  for (std::uint32_t part = 0; part <= max_part; ++part) {
    in.clear();
    for (std::size_t t = 0; t < count; ++t)
      if (m.parts[t] == part) in.insert(in.end(), m.triangles.begin() + 3 * t, m.triangles.begin() + 3 * t + 3);
    if (in.empty()) continue;
    const std::size_t target_triangles =
        std::max<std::size_t>(1, static_cast<std::size_t>(static_cast<double>(budget) * (in.size() / 3) / count));
    const unsigned options = max_part > 0 ? static_cast<unsigned>(meshopt_SimplifyLockBorder) : 0u;
    dst.resize(in.size());
    float error = 0.0f;
    std::size_t n = 0;
    if (mode != Mode::kSloppy) {
      n = meshopt_simplify(dst.data(), in.data(), in.size(), m.positions_m.data(), vertex_count, 12,
                           3 * target_triangles, target_error, options, &error);
    }
    if (mode == Mode::kSloppy || (mode == Mode::kSimplifyThenSloppy && n > 3 * target_triangles)) {
      // Sloppy from the input (its grid search wants the full mesh).
      n = meshopt_simplifySloppy(dst.data(), in.data(), in.size(), m.positions_m.data(), vertex_count, 12,
                                 3 * target_triangles, std::numeric_limits<float>::max(), &error);
      sloppy_used = true;
    }
    worst_error = std::max(worst_error, error);
    out.vertices.insert(out.vertices.end(), dst.begin(), dst.begin() + static_cast<std::ptrdiff_t>(n));
    out.parts.insert(out.parts.end(), n / 3, static_cast<std::uint16_t>(part));
  }
  char note[96];
  std::snprintf(note, sizeof note, "result_error %.2e rel = %.1f um%s", worst_error,
                worst_error * meshopt_simplifyScale(m.positions_m.data(), vertex_count, 12) * 1e6,
                sloppy_used ? ", sloppy" : "");
  out.note = note;
  return out;
}

// ---------------------------------------------------------------- geometry

using V3 = std::array<double, 3>;
V3 Sub(const V3& a, const V3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
V3 Add(const V3& a, const V3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
V3 Mul(const V3& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
double Dot(const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
V3 Cross(const V3& a, const V3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double Norm(const V3& a) { return std::sqrt(Dot(a, a)); }
V3 At(const std::vector<float>& p, std::uint32_t v) { return {p[3 * v], p[3 * v + 1], p[3 * v + 2]}; }

// Closest point on triangle abc to p (Ericson, Real-Time Collision Detection 5.1.5).
V3 ClosestOnTriangle(const V3& p, const V3& a, const V3& b, const V3& c) {
  const V3 ab = Sub(b, a), ac = Sub(c, a), ap = Sub(p, a);
  const double d1 = Dot(ab, ap), d2 = Dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const V3 bp = Sub(p, b);
  const double d3 = Dot(ab, bp), d4 = Dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return Add(a, Mul(ab, d1 / (d1 - d3)));
  const V3 cp = Sub(p, c);
  const double d5 = Dot(ab, cp), d6 = Dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return Add(a, Mul(ac, d2 / (d2 - d6)));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return Add(b, Mul(Sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6))));
  const double denom = 1.0 / (va + vb + vc);
  return Add(a, Add(Mul(ab, vb * denom), Mul(ac, vc * denom)));
}

// Uniform grid of triangles; nearest-triangle distance by rings of cells.
class TriangleGrid {
 public:
  TriangleGrid(const std::vector<float>& p, const std::vector<std::uint32_t>& tri, const V3& lo, const V3& hi,
               double cell)
      : p_(p), tri_(tri), lo_(lo), cell_(cell) {
    for (int k = 0; k < 3; ++k) n_[k] = std::max(1, static_cast<int>(std::ceil((hi[k] - lo[k]) / cell)) + 1);
    std::vector<std::uint32_t> counts(static_cast<std::size_t>(n_[0]) * n_[1] * n_[2] + 1, 0);
    auto for_cells = [&](std::size_t t, const std::function<void(std::size_t)>& f) {
      int a[3], b[3];
      for (int k = 0; k < 3; ++k) {
        double mn = 1e30, mx = -1e30;
        for (int j = 0; j < 3; ++j) {
          const double x = p_[3 * tri_[3 * t + j] + k];
          mn = std::min(mn, x);
          mx = std::max(mx, x);
        }
        a[k] = Clamp(static_cast<int>(std::floor((mn - lo_[k]) / cell_)), k);
        b[k] = Clamp(static_cast<int>(std::floor((mx - lo_[k]) / cell_)), k);
      }
      for (int z = a[2]; z <= b[2]; ++z)
        for (int y = a[1]; y <= b[1]; ++y)
          for (int x = a[0]; x <= b[0]; ++x) f(Index(x, y, z));
    };
    const std::size_t tris = tri_.size() / 3;
    for (std::size_t t = 0; t < tris; ++t) for_cells(t, [&](std::size_t c) { ++counts[c + 1]; });
    for (std::size_t c = 1; c < counts.size(); ++c) counts[c] += counts[c - 1];
    start_ = counts;
    items_.resize(start_.back());
    std::vector<std::uint32_t> next(start_.begin(), start_.end() - 1);
    for (std::size_t t = 0; t < tris; ++t)
      for_cells(t, [&](std::size_t c) { items_[next[c]++] = static_cast<std::uint32_t>(t); });
    stamp_.assign(tris, 0);
  }

  double Distance(const V3& q, std::uint32_t* closest_tri = nullptr, V3* closest = nullptr) {
    ++query_;
    std::uint32_t best_t = 0;
    V3 best_on{0, 0, 0};
    int c[3];
    for (int k = 0; k < 3; ++k) c[k] = Clamp(static_cast<int>(std::floor((q[k] - lo_[k]) / cell_)), k);
    double best2 = std::numeric_limits<double>::infinity();
    const int max_r = std::max({n_[0], n_[1], n_[2]});
    for (int r = 0; r <= max_r; ++r) {
      for (int z = c[2] - r; z <= c[2] + r; ++z) {
        if (z < 0 || z >= n_[2]) continue;
        for (int y = c[1] - r; y <= c[1] + r; ++y) {
          if (y < 0 || y >= n_[1]) continue;
          for (int x = c[0] - r; x <= c[0] + r; ++x) {
            if (x < 0 || x >= n_[0]) continue;
            if (std::max({std::abs(x - c[0]), std::abs(y - c[1]), std::abs(z - c[2])}) != r) continue;
            const std::size_t cell = Index(x, y, z);
            for (std::uint32_t i = start_[cell]; i < start_[cell + 1]; ++i) {
              const std::uint32_t t = items_[i];
              if (stamp_[t] == query_) continue;
              stamp_[t] = query_;
              const V3 on = ClosestOnTriangle(q, At(p_, tri_[3 * t]), At(p_, tri_[3 * t + 1]), At(p_, tri_[3 * t + 2]));
              const double d2 = Dot(Sub(q, on), Sub(q, on));
              if (d2 < best2) {
                best2 = d2;
                best_t = t;
                best_on = on;
              }
            }
          }
        }
      }
      // Every triangle not yet seen lies outside the (2r+1)^3 block around
      // q's cell, i.e. at least r cells away.
      if (best2 <= (r * cell_) * (r * cell_)) break;
    }
    if (closest_tri) *closest_tri = best_t;
    if (closest) *closest = best_on;
    return std::sqrt(best2);
  }

 private:
  int Clamp(int i, int k) const { return std::min(std::max(i, 0), n_[k] - 1); }
  std::size_t Index(int x, int y, int z) const {
    return (static_cast<std::size_t>(z) * n_[1] + static_cast<std::size_t>(y)) * n_[0] + static_cast<std::size_t>(x);
  }
  const std::vector<float>& p_;
  const std::vector<std::uint32_t>& tri_;
  V3 lo_;
  double cell_;
  int n_[3];
  std::vector<std::uint32_t> start_, items_, stamp_;
  std::uint32_t query_ = 0;
};

// Sample points of a mesh: every vertex used + `samples` area-weighted random
// points (with their triangle and barycentrics; tri = ~0u for the vertices).
struct Sample {
  V3 p;
  std::uint32_t tri = ~0u;
  double b[3] = {0, 0, 0};
};
std::vector<Sample> Samples(const std::vector<float>& p, const std::vector<std::uint32_t>& tri, std::size_t samples,
                        std::uint32_t seed) {
  std::vector<Sample> out;
  std::vector<std::uint8_t> used(p.size() / 3, 0);
  for (const auto v : tri)
    if (!used[v]) {
      used[v] = 1;
      out.push_back({At(p, v)});
    }
  const std::size_t tris = tri.size() / 3;
  std::vector<double> cumulative(tris);
  double total = 0;
  for (std::size_t t = 0; t < tris; ++t) {
    const V3 a = At(p, tri[3 * t]), b = At(p, tri[3 * t + 1]), c = At(p, tri[3 * t + 2]);
    total += 0.5 * Norm(Cross(Sub(b, a), Sub(c, a)));
    cumulative[t] = total;
  }
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (std::size_t i = 0; i < samples; ++i) {
    const std::size_t t = std::min<std::size_t>(
        tris - 1, static_cast<std::size_t>(std::lower_bound(cumulative.begin(), cumulative.end(), u(rng) * total) -
                                           cumulative.begin()));
    double r1 = u(rng), r2 = u(rng);
    if (r1 + r2 > 1) {
      r1 = 1 - r1;
      r2 = 1 - r2;
    }
    const V3 a = At(p, tri[3 * t]), b = At(p, tri[3 * t + 1]), c = At(p, tri[3 * t + 2]);
    out.push_back({Add(a, Add(Mul(Sub(b, a), r1), Mul(Sub(c, a), r2))), static_cast<std::uint32_t>(t), {1 - r1 - r2, r1, r2}});
  }
  return out;
}

struct OneWay {
  double rms = 0, max = 0;
};
OneWay Measure(const std::vector<Sample>& from, TriangleGrid& to) {
  OneWay o;
  double sum2 = 0;
  for (const Sample& s : from) {
    const double d = to.Distance(s.p);
    sum2 += d * d;
    o.max = std::max(o.max, d);
  }
  o.rms = std::sqrt(sum2 / static_cast<double>(from.size()));
  return o;
}

struct Quality {
  OneWay coarse_to_full, full_to_coarse;
  double diag = 0;
  double thin = 0;        // fraction of triangles with min angle < 10 deg
  std::size_t flipped = 0;     // coarse normal . mean full-mesh normal at its corners < 0 (area > 1% of a full triangle's)
  double flipped_area = 0;     // their share of the coarse mesh's area
  std::size_t degenerate = 0;  // area <= 1% of the mean full triangle's (draw nothing)
  double shade_mean_deg = 0, shade_p99_deg = 0, shade_max_deg = 0;  // see Evaluate
  double max_edge_mm = 0;
};

Quality Evaluate(const std::vector<float>& p, const std::vector<std::uint32_t>& full, const Coarse& coarse) {
  Quality q;
  V3 lo = {1e30, 1e30, 1e30}, hi = {-1e30, -1e30, -1e30};
  for (std::size_t i = 0; i < p.size(); ++i) {
    lo[i % 3] = std::min(lo[i % 3], static_cast<double>(p[i]));
    hi[i % 3] = std::max(hi[i % 3], static_cast<double>(p[i]));
  }
  q.diag = Norm(Sub(hi, lo));
  const double cell = 0.5e-3;
  TriangleGrid full_grid(p, full, lo, hi, cell), coarse_grid(p, coarse.vertices, lo, hi, cell);
  constexpr std::size_t kSamples = 100000;
  const std::vector<Sample> coarse_samples = Samples(p, coarse.vertices, kSamples, 1);
  q.coarse_to_full = Measure(coarse_samples, full_grid);
  q.full_to_coarse = Measure(Samples(p, full, kSamples, 2), coarse_grid);
  // Full-mesh vertex normals (area-weighted, as vertex_normals.h).
  std::vector<V3> n(p.size() / 3, V3{0, 0, 0});
  double full_area = 0;
  for (std::size_t t = 0; t < full.size() / 3; ++t) {
    const V3 a = At(p, full[3 * t]), b = At(p, full[3 * t + 1]), c = At(p, full[3 * t + 2]);
    const V3 f = Cross(Sub(b, a), Sub(c, a));
    full_area += 0.5 * Norm(f);
    for (int k = 0; k < 3; ++k) n[full[3 * t + k]] = Add(n[full[3 * t + k]], f);
  }
  const double small_area = 0.01 * full_area / static_cast<double>(full.size() / 3);
  // Shading proxy: the viewer lights per vertex with the FULL mesh's normals,
  // so a coarse triangle shows its corners' full normals interpolated across
  // it. Angle between that and the full mesh's own interpolated normal at the
  // nearest point of the full surface, over the coarse mesh's random samples.
  auto interpolated = [&](const std::vector<std::uint32_t>& tri, std::uint32_t t, const double b[3]) {
    V3 m{0, 0, 0};
    for (int k = 0; k < 3; ++k) {
      const V3& nk = n[tri[3 * t + k]];
      m = Add(m, Mul(nk, b[k] / (Norm(nk) + 1e-300)));
    }
    return Mul(m, 1.0 / (Norm(m) + 1e-300));
  };
  std::vector<double> angles;
  for (const Sample& s : coarse_samples) {
    if (s.tri == ~0u) continue;
    std::uint32_t ft = 0;
    V3 on;
    full_grid.Distance(s.p, &ft, &on);
    // Barycentrics of `on` in full triangle ft.
    const V3 a = At(p, full[3 * ft]), b = At(p, full[3 * ft + 1]), c = At(p, full[3 * ft + 2]);
    const V3 v0 = Sub(b, a), v1 = Sub(c, a), v2 = Sub(on, a);
    const double d00 = Dot(v0, v0), d01 = Dot(v0, v1), d11 = Dot(v1, v1), d20 = Dot(v2, v0), d21 = Dot(v2, v1);
    const double den = d00 * d11 - d01 * d01;
    const double bv = (d11 * d20 - d01 * d21) / den, bw = (d00 * d21 - d01 * d20) / den;
    const double fb[3] = {1 - bv - bw, bv, bw};
    const double cosang = Dot(interpolated(coarse.vertices, s.tri, s.b), interpolated(full, ft, fb));
    angles.push_back(std::acos(std::max(-1.0, std::min(1.0, cosang))) * 180 / M_PI);
  }
  if (!angles.empty()) {
    double sum = 0;
    for (const double x : angles) sum += x;
    q.shade_mean_deg = sum / static_cast<double>(angles.size());
    std::sort(angles.begin(), angles.end());
    q.shade_p99_deg = angles[static_cast<std::size_t>(0.99 * static_cast<double>(angles.size() - 1))];
    q.shade_max_deg = angles.back();
  }
  std::size_t thin = 0;
  double coarse_area = 0;
  const std::size_t tris = coarse.vertices.size() / 3;
  for (std::size_t t = 0; t < tris; ++t) {
    const std::uint32_t ia = coarse.vertices[3 * t], ib = coarse.vertices[3 * t + 1], ic = coarse.vertices[3 * t + 2];
    const V3 a = At(p, ia), b = At(p, ib), c = At(p, ic);
    const V3 f = Cross(Sub(b, a), Sub(c, a));
    if (0.5 * Norm(f) <= small_area)
      ++q.degenerate;
    else if (Dot(f, Add(n[ia], Add(n[ib], n[ic]))) < 0) {
      ++q.flipped;
      q.flipped_area += 0.5 * Norm(f);
    }
    coarse_area += 0.5 * Norm(f);
    const V3 e[3] = {Sub(b, a), Sub(c, b), Sub(a, c)};
    double min_angle = 180;
    for (int k = 0; k < 3; ++k) {
      const V3 u = e[k], v = Mul(e[(k + 2) % 3], -1.0);  // angle at the start vertex of e[k]
      const double cosang = Dot(u, v) / (Norm(u) * Norm(v) + 1e-300);
      min_angle = std::min(min_angle, std::acos(std::max(-1.0, std::min(1.0, cosang))) * 180 / M_PI);
      q.max_edge_mm = std::max(q.max_edge_mm, Norm(e[k]) * 1e3);
    }
    if (min_angle < 10) ++thin;
  }
  q.thin = tris ? static_cast<double>(thin) / static_cast<double>(tris) : 0;
  q.flipped_area = coarse_area > 0 ? q.flipped_area / coarse_area : 0;
  return q;
}

double MedianMs(const std::function<Coarse()>& f, Coarse* keep) {
  for (int i = 0; i < 2; ++i) *keep = f();
  std::vector<double> ms;
  for (int i = 0; i < kRuns; ++i) {
    const auto t0 = Clock::now();
    Coarse c = f();
    const auto t1 = Clock::now();
    ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    if (i == kRuns - 1) *keep = std::move(c);
  }
  std::nth_element(ms.begin(), ms.begin() + kRuns / 2, ms.end());
  return ms[kRuns / 2];
}

}  // namespace

int main(int argc, char** argv) {
  const bool time_only = argc > 1 && std::strcmp(argv[1], "--time-only") == 0;
  const int kGrid = 224;
  const SheetMesh rest = Sheet(kGrid);  // what the viewer is sent (the keyframe)
  const SheetMesh flat = Sheet(kGrid, {});  // the same sheet before the tool touches it
  // Later positions of the same slots (deltas: topology unchanged, the coarse list is NOT recomputed).
  const std::vector<float> moved_dent = SheetPositions(kGrid, {Dent{0.006, 0.015, -0.010, 1e-4}});
  const std::vector<float> poke = SheetPositions(kGrid, {Dent{}, Dent{0.003, -0.012, 0.012, 1e-5}});
  std::printf("meshoptimizer 0.%d (MESHOPTIMIZER_VERSION %d), mesh: %zu vertices, %zu triangles, one part; %d runs per timing (median)\n",
              MESHOPTIMIZER_VERSION / 10, MESHOPTIMIZER_VERSION, rest.positions_m.size() / 3,
              rest.parts.size(), kRuns);

  struct Method {
    std::string name;
    std::function<Coarse(const SheetMesh&, std::size_t)> run;
  };
  std::vector<Method> methods = {
      {"ours SimplifyToBudget", Ours},
      {"meshopt_simplify e=1e-2 (+sloppy)",
       [](const SheetMesh& m, std::size_t b) { return Meshopt(m, b, Mode::kSimplifyThenSloppy, 1e-2f); }},
      {"meshopt_simplify e=1e-4 (+sloppy)",
       [](const SheetMesh& m, std::size_t b) { return Meshopt(m, b, Mode::kSimplifyThenSloppy, 1e-4f); }},
      {"meshopt_simplify e=inf",
       [](const SheetMesh& m, std::size_t b) {
         return Meshopt(m, b, Mode::kSimplify, std::numeric_limits<float>::max());
       }},
      {"meshopt_simplifySloppy",
       [](const SheetMesh& m, std::size_t b) { return Meshopt(m, b, Mode::kSloppy, 0.0f); }},
  };

  if (!time_only) {  // sanity of the measure: the full mesh against itself
    const Quality q = Evaluate(rest.positions_m, rest.triangles, Coarse{rest.triangles, rest.parts, ""});
    std::printf("sanity, full vs full: max %.3g um, shading max %.3g deg, flipped %zu\n",
                std::max(q.coarse_to_full.max, q.full_to_coarse.max) * 1e6, q.shade_max_deg, q.flipped);
  }
  for (const std::size_t budget : {std::size_t{50000}, std::size_t{25000}, std::size_t{10000}}) {
    std::printf("\n=== budget %zu triangles ===\n", budget);
    std::size_t ours_count = 0;
    std::vector<Method> all = methods;
    for (std::size_t mi = 0; mi <= all.size(); ++mi) {
      if (mi == all.size()) {
        if (ours_count == 0 || all.size() > methods.size()) break;
        // meshopt at exactly ours' triangle count: quality at equal cost to draw.
        const std::size_t n = ours_count;
        all.push_back({"meshopt_simplify e=inf @ours' count", [n](const SheetMesh& m, std::size_t) {
                         return Meshopt(m, n, Mode::kSimplify, std::numeric_limits<float>::max());
                       }});
      }
      const Method& method = all[mi];
      Coarse c;
      const double ms = MedianMs([&] { return method.run(rest, budget); }, &c);
      if (mi == 0) ours_count = c.parts.size();
      std::printf("%-38s %8.2f ms  %6zu tris  %s\n", method.name.c_str(), ms, c.parts.size(), c.note.c_str());
      if (time_only) continue;
      struct Scenario {
        const char* name;
        const std::vector<float>* positions;  // evaluated on these
        const SheetMesh* simplified_on;       // coarse list computed on this shape
      };
      const Scenario scenarios[] = {
          {"as simplified (keyframe shape)", &rest.positions_m, &rest},
          {"then dent moved+deepened 6 mm", &moved_dent, &rest},
          {"then sharp 3 mm poke (r~3 mm)", &poke, &rest},
          {"keyframe flat, then bench dent", &rest.positions_m, &flat},
      };
      for (const Scenario& s : scenarios) {
        const Coarse coarse = s.simplified_on == &rest ? c : method.run(*s.simplified_on, budget);
        const Quality q = Evaluate(*s.positions, rest.triangles, coarse);
        const double rms = std::sqrt(0.5 * (q.coarse_to_full.rms * q.coarse_to_full.rms +
                                            q.full_to_coarse.rms * q.full_to_coarse.rms));
        const double mx = std::max(q.coarse_to_full.max, q.full_to_coarse.max);
        std::printf(
            "    %-32s c->f rms %6.1f max %6.1f | f->c rms %6.1f max %6.1f um | sym rms %6.1f um (%.1e diag) max %6.1f "
            "um (%.1e diag) | thin<10deg %4.1f%% flipped %zu (%.3f%% of area) degenerate %zu maxedge %.2f mm | shading deg mean %.2f p99 %.1f max %.1f\n",
            s.name, q.coarse_to_full.rms * 1e6, q.coarse_to_full.max * 1e6, q.full_to_coarse.rms * 1e6,
            q.full_to_coarse.max * 1e6, rms * 1e6, rms / q.diag, mx * 1e6, mx / q.diag, 100 * q.thin, q.flipped,
            100 * q.flipped_area, q.degenerate, q.max_edge_mm, q.shade_mean_deg, q.shade_p99_deg, q.shade_max_deg);
      }
    }
  }
  return 0;
}
