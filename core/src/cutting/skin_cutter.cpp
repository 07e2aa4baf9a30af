#include "hapsim/core/cutting/skin_cutter.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "hapsim/core/msm/msm_topology.h"

namespace hapsim::core {

namespace {

constexpr std::uint32_t kLipFlag = 0x80000000u;  // a Tri entry naming lips_[i], not a node
constexpr double kOnCurve_m = 1e-9;              // a node this close to the curve is on it
constexpr int kPolylineSamples = 9;              // the segment as 8 straight pieces (stage-1 distances)

double PointSegmentDistance2D(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector2d ab = (b - a).head<2>(), ap = (p - a).head<2>();
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp(ap.dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (ap - t * ab).norm();
}

double Cross2D(const Eigen::Vector2d& u, const Eigen::Vector2d& v) { return u.x() * v.y() - u.y() * v.x(); }

bool SegmentsIntersect2D(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                         const Eigen::Vector3d& d) {
  const Eigen::Vector2d r = (b - a).head<2>(), s = (d - c).head<2>(), ca = (c - a).head<2>();
  const double den = Cross2D(r, s);
  if (den == 0.0) return false;  // parallel: the distance test decides
  const double t = Cross2D(ca, s) / den, u = Cross2D(ca, r) / den;
  return t >= 0.0 && t <= 1.0 && u >= 0.0 && u <= 1.0;
}

double SignedArea2D(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  return 0.5 * Cross2D((b - a).head<2>(), (c - a).head<2>());
}

// The incision curve's end parameter (its segment count).
double CurveEndParam(const IncisionCurve& curve) { return static_cast<double>(curve.Segments()); }

}  // namespace

CutStats& CutStats::operator+=(const CutStats& o) {
  triangles_removed += o.triangles_removed;
  triangles_added += o.triangles_added;
  nodes_removed += o.nodes_removed;
  nodes_added += o.nodes_added;
  springs_removed += o.springs_removed;
  springs_added += o.springs_added;
  skipped_triangles += o.skipped_triangles;
  springs_refused += o.springs_refused;
  refused = refused || o.refused;
  return *this;
}

SkinCutter::SkinCutter(const SkinMesh& skin) {
  const std::size_t nv = skin.topology.Vertices().Capacity(), nt = skin.topology.Triangles().Capacity();
  polyline_.reserve(kPolylineSamples);
  inside_.reserve(nv);
  removed_triangles_.reserve(nt);
  triangle_mark_.assign(nt, 0);
  next_.assign(nv, kNoSlot);
  has_prev_.assign(nv, 0);
  border_nodes_.reserve(nv);
  chain_.reserve(nv);
  chain_start_.reserve(nv + 1);
  chain_closed_.reserve(nv);
  lips_.reserve(nv);
  params_.reserve(nv);
  left_lips_.reserve(nv);
  right_lips_.reserve(nv);
  run_.reserve(nv);
  fan_ok_.reserve(nv);
  new_triangles_.reserve(2 * nv);
  new_springs_.reserve(6 * nv);
  lip_nodes_.reserve(nv);
  touched_.reserve(nv);
  touched_mark_.assign(nv, 0);
}

double SkinCutter::DistanceToSegment(const Eigen::Vector3d& p) const {
  double d = std::numeric_limits<double>::infinity();
  // Most nodes of the patch are far from the segment: a lower bound from
  // the polyline's box rejects them without the per-piece distances.
  const Eigen::Vector2d q = p.head<2>();
  const double box_gap = (q - q.cwiseMax(polyline_lo_).cwiseMin(polyline_hi_)).norm();
  if (box_gap > far_m_) return box_gap;
  for (std::size_t i = 0; i + 1 < polyline_.size(); ++i) d = std::min(d, PointSegmentDistance2D(p, polyline_[i], polyline_[i + 1]));
  return d;
}

bool SkinCutter::SegmentCrossesZone(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const {
  for (std::size_t i = 0; i + 1 < polyline_.size(); ++i) {
    const Eigen::Vector3d& c = polyline_[i];
    const Eigen::Vector3d& d = polyline_[i + 1];
    if (SegmentsIntersect2D(a, b, c, d)) return true;
    const double dist = std::min({PointSegmentDistance2D(a, c, d), PointSegmentDistance2D(b, c, d),
                                  PointSegmentDistance2D(c, a, b), PointSegmentDistance2D(d, a, b)});
    if (dist < zone_radius_m_) return true;
  }
  return false;
}

// Walks the hole's border (next_) into chains, matches each border node to
// the curve (stage 3) and decides its wound node (lips_).
bool SkinCutter::PlanChains(const SkinMesh& skin, const IncisionCurve& curve) {
  lips_.clear();
  if (!WalkBorderChains()) return false;
  MatchBorderToCurve(skin, curve);
  if (chain_closed_.size() == 1 && chain_closed_[0] != 0) StartLoopAtCurveStart();  // the hole is one loop
  KeepMatchesFromFolding(CurveEndParam(curve));
  PlaceCurveLips(skin, curve);
  CollectSharedParams(skin, curve);
  left_lips_.assign(params_.size(), kNoSlot);
  right_lips_.assign(params_.size(), kNoSlot);
  // Chain by chain: a later chain's old lip may take over a shared
  // parameter an earlier chain's side node made a wound node at.
  for (std::size_t c = 0; c + 1 < chain_start_.size(); ++c) {
    AssignOldLipSides(c, CurveEndParam(curve));
    LinkSideNodes(curve, c);
  }
  return true;
}

// Appends the chain from start along next_ to chain_; false if a loop does
// not come back to its start.
bool SkinCutter::WalkChain(std::uint32_t start, bool closed) {
  chain_start_.push_back(static_cast<std::uint32_t>(chain_.size()));
  chain_closed_.push_back(closed ? 1 : 0);
  std::uint32_t v = start;
  std::size_t guard = 0;
  do {
    chain_.push_back({v, 0.0, 0, 0});
    has_prev_[v] = 2;  // visited
    v = next_[v];
  } while (v != kNoSlot && v != start && has_prev_[v] != 2 && ++guard < next_.size());
  return !closed || v == start;
}

// Chains: open ones start at a border node nothing leads to; the rest are
// loops. False for a hole one ladder of triangles cannot fill.
bool SkinCutter::WalkBorderChains() {
  chain_.clear();
  chain_start_.clear();
  chain_closed_.clear();
  for (const std::uint32_t b : border_nodes_)
    if (has_prev_[b] == 0 && !WalkChain(b, false)) return false;
  for (const std::uint32_t b : border_nodes_)
    if (has_prev_[b] == 1 && !WalkChain(b, true)) return false;
  chain_start_.push_back(static_cast<std::uint32_t>(chain_.size()));
  std::size_t loops = 0;
  for (const auto c : chain_closed_) loops += c;
  return !(loops > 1 || (loops == 1 && chain_closed_.size() > 1));
}

// Stage 3: every border node matched to the curve (parameter and side).
void SkinCutter::MatchBorderToCurve(const SkinMesh& skin, const IncisionCurve& curve) {
  const int k = curve.Segments() - 1;
  const double end_s = CurveEndParam(curve);
  for (ChainNode& c : chain_) {
    const Eigen::Vector3d& p = skin.model.x0_m.col(c.node);
    const IncisionCurve::Projection proj = curve.Project(p.head<2>(), std::max(0, k - 3), k);
    c.s = proj.s;
    if (proj.s >= end_s - 1e-9) {
      c.side = 0;  // matched to the curve's end
      c.s = end_s;
    } else if (proj.distance_m < kOnCurve_m && skin.on_lip[c.node]) {
      c.side = 0;  // a lip from before: it is its own wound node
    } else if (proj.s <= 1e-9) {
      c.side = 0;  // matched to the curve's start (behind it)
      c.s = 0.0;
    } else {
      c.side = proj.side != 0 ? proj.side : 1;
    }
  }
}

// A loop (the hole holds the incision's start) starts at a node matched
// to the curve's start, so the walk (hole on its right: clockwise) runs up the
// left lip, round the end and back down the right lip.
void SkinCutter::StartLoopAtCurveStart() {
  const auto n = chain_.size();
  std::size_t start = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (chain_[i].side == 0 && chain_[i].s == 0.0) {
      start = i;
      break;
    }
  }
  std::rotate(chain_.begin(), chain_.begin() + static_cast<std::ptrdiff_t>(start), chain_.end());
}

// Matches must not fold back: along the walk the left lip's parameter
// only grows, the right lip's only shrinks, and neither passes a border
// node already on the curve (an old lip) next to it — a folding match
// shares its neighbour's wound node instead. Forward for the left side,
// backward for the right.
void SkinCutter::KeepMatchesFromFolding(double end_s) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  for (std::size_t c = 0; c + 1 < chain_start_.size(); ++c) {
    double run = -kInf;
    for (std::uint32_t i = chain_start_[c]; i < chain_start_[c + 1]; ++i) {
      ChainNode& n = chain_[i];
      if (n.side == 0 && n.s != end_s) run = std::max(run, n.s);
      if (n.side > 0) run = n.s = std::max(n.s, run);
    }
    run = -kInf;
    for (std::uint32_t i = chain_start_[c + 1]; i-- > chain_start_[c];) {
      ChainNode& n = chain_[i];
      if (n.side == 0 && n.s != end_s) run = std::max(run, n.s);
      if (n.side < 0) run = n.s = std::max(n.s, run);
    }
  }
}

// Wound nodes: one shared end node; one shared start node (the old one
// if it is on the hole's border, a new one if the hole swallowed it or
// this is the first segment); a border node on the curve is its own. Side
// nodes get theirs later (LinkSideNodes).
void SkinCutter::PlaceCurveLips(const SkinMesh& skin, const IncisionCurve& curve) {
  const double end_s = CurveEndParam(curve);
  std::uint32_t end_lip = kNoSlot, start_lip = kNoSlot;
  for (std::uint32_t i = 0; i < chain_.size(); ++i) {
    ChainNode& n = chain_[i];
    n.lip = kNoSlot;
    if (n.side == 0 && n.s != end_s && skin.on_lip[n.node] &&
        (skin.model.x0_m.col(n.node).head<2>() - curve.FirstPoint()).norm() < kOnCurve_m) {
      start_lip = static_cast<std::uint32_t>(lips_.size());  // the old start node, still on the border
      lips_.push_back({skin.model.x0_m.col(n.node), i, n.node});
      n.lip = start_lip;
    }
  }
  for (std::uint32_t i = 0; i < chain_.size(); ++i) {
    ChainNode& n = chain_[i];
    if (n.lip != kNoSlot) continue;
    const Eigen::Vector2d at = curve.Point(n.s);
    const Eigen::Vector3d rest(at.x(), at.y(), 0.0);
    const bool at_start = n.s == 0.0 && !(skin.on_lip[n.node] && (skin.model.x0_m.col(n.node).head<2>() - at).norm() < kOnCurve_m);
    if (n.side == 0 && n.s == end_s) {
      if (end_lip == kNoSlot) {
        end_lip = static_cast<std::uint32_t>(lips_.size());
        lips_.push_back({rest, i, kNoSlot});
      }
      n.lip = end_lip;
    } else if (n.side == 0 && at_start) {
      if (start_lip == kNoSlot) {
        start_lip = static_cast<std::uint32_t>(lips_.size());
        lips_.push_back({rest, i, kNoSlot});
      }
      n.lip = start_lip;
    } else if (n.side == 0) {
      n.lip = static_cast<std::uint32_t>(lips_.size());
      lips_.push_back({skin.model.x0_m.col(n.node), i, n.node});
    }
  }
}

bool SkinCutter::IsOwnLip(const ChainNode& n) const { return n.lip != kNoSlot && lips_[n.lip].node == n.node; }

// Side nodes: the matches of both sides form one sorted set of curve
// parameters (params_), and each side gets a wound node at every one of
// them — the two lips then pass through the same curve points and close
// exactly at rest, however the curve bends. A match equal to a
// neighbouring old lip's parameter is that lip.
void SkinCutter::CollectSharedParams(const SkinMesh& skin, const IncisionCurve& curve) {
  const double end_s = CurveEndParam(curve);
  // (Old lips count as matches too: the other side gets a node there.)
  params_.clear();
  for (const ChainNode& n : chain_)
    if (n.side != 0 || (IsOwnLip(n) && n.s > 0.0 && n.s < end_s)) params_.push_back(n.s);
  std::sort(params_.begin(), params_.end());
  MergeCloseParams(skin, curve);
  SnapSideMatches();
}

// Matches closer than a third of a spacing along the curve share one wound
// node (else the quadrilaterals between them are slivers); old lips keep
// theirs.
void SkinCutter::MergeCloseParams(const SkinMesh& skin, const IncisionCurve& curve) {
  const double merge_m = skin.def.spacing_m / 3.0;
  auto arc_gap = [&](double a, double b) {
    const int seg = std::clamp(static_cast<int>(a), 0, curve.Segments() - 1);
    const auto& c = curve.Controls(seg);
    return (b - a) * (c[3] - c[0]).norm();  // chord length per unit of parameter
  };
  auto is_old_lip = [&](double v) {
    for (const ChainNode& n : chain_)
      if (n.side == 0 && IsOwnLip(n) && std::abs(n.s - v) < 1e-12) return true;
    return false;
  };
  std::size_t kept = 0;
  for (std::size_t m = 0; m < params_.size(); ++m) {
    if (kept > 0 && arc_gap(params_[kept - 1], params_[m]) < merge_m && !is_old_lip(params_[m])) continue;
    params_[kept++] = params_[m];
  }
  params_.resize(kept);
}

// Every side match snaps to its nearest shared parameter.
void SkinCutter::SnapSideMatches() {
  for (ChainNode& n : chain_) {
    if (n.side == 0 || params_.empty()) continue;
    const auto it = std::lower_bound(params_.begin(), params_.end(), n.s);
    double snapped = it == params_.end() ? params_.back() : *it;
    if (it != params_.begin() && (it == params_.end() || n.s - *(it - 1) < *it - n.s)) snapped = *(it - 1);
    n.s = snapped;
  }
}

// The border node step places along chain c from chain entry i (-1 back,
// +1 on); nullptr past an open chain's ends.
const SkinCutter::ChainNode* SkinCutter::ChainNeighbour(std::size_t c, std::uint32_t i, int step) const {
  const std::uint32_t first_i = chain_start_[c], len = chain_start_[c + 1] - first_i;
  const std::uint32_t local = i - first_i;
  if (chain_closed_[c] == 0 && ((step < 0 && local == 0) || (step > 0 && local + 1 == len))) return nullptr;
  return &chain_[first_i + (local + len + static_cast<std::uint32_t>(len + step)) % len];
}

// An old lip in chain c sits on the side of the border nodes next to it:
// it is that side's wound node at its parameter.
void SkinCutter::AssignOldLipSides(std::size_t c, double end_s) {
  for (std::uint32_t i = chain_start_[c]; i < chain_start_[c + 1]; ++i) {
    const ChainNode& n = chain_[i];
    if (n.side != 0 || !IsOwnLip(n) || !(n.s > 0.0 && n.s < end_s)) continue;
    int side = 0;
    for (const int step : {1, -1}) {
      const ChainNode* m = ChainNeighbour(c, i, step);
      if (m && m->side != 0) {
        side = m->side;
        break;
      }
    }
    if (side != 0) (side > 0 ? left_lips_ : right_lips_)[ParamIndex(n.s)] = n.lip;
  }
}

// Each side node of chain c takes a neighbouring old lip at its parameter,
// else its side's wound node there (made on first use).
void SkinCutter::LinkSideNodes(const IncisionCurve& curve, std::size_t c) {
  for (std::uint32_t i = chain_start_[c]; i < chain_start_[c + 1]; ++i) {
    ChainNode& n = chain_[i];
    if (n.side == 0) continue;
    for (const int step : {-1, 1}) {
      const ChainNode* m = ChainNeighbour(c, i, step);
      if (m && m->side == 0 && IsOwnLip(*m) && std::abs(m->s - n.s) < 1e-12) {
        n.lip = m->lip;
        break;
      }
    }
    if (n.lip == kNoSlot) n.lip = SideLip(curve, n.side, ParamIndex(n.s), i);
  }
}

std::size_t SkinCutter::ParamIndex(double s) const {
  const auto it = std::lower_bound(params_.begin(), params_.end(), s - 1e-12);
  return std::min(static_cast<std::size_t>(it - params_.begin()), params_.size() - 1);
}

std::uint32_t SkinCutter::SideLip(const IncisionCurve& curve, int side, std::size_t k, std::uint32_t from_chain) {
  std::uint32_t& lip = (side > 0 ? left_lips_ : right_lips_)[k];
  if (lip == kNoSlot) {
    const Eigen::Vector2d at = curve.Point(params_[k]);
    lip = static_cast<std::uint32_t>(lips_.size());
    lips_.push_back({Eigen::Vector3d(at.x(), at.y(), 0.0), from_chain, kNoSlot});
  }
  return lip;
}

// Between consecutive border nodes a -> b (the hole on the right) and the
// run of wound nodes from a's match to b's along the curve (every shared
// parameter in between, on their side), triangles zip the border pair to
// the run: at each step the shorter diagonal wins (the paper's "connect the
// shorter diagonal" of each quadrilateral). Degenerate triangles (a border
// node that is its own wound node) are left out: they have no area.
void SkinCutter::PlanTriangles(const SkinMesh& skin, const IncisionCurve& curve) {
  new_triangles_.clear();
  planned_skips_ = 0;
  for (std::size_t c = 0; c + 1 < chain_start_.size(); ++c) {
    const std::uint32_t first = chain_start_[c], last = chain_start_[c + 1];
    const std::uint32_t pairs = (last - first) - (chain_closed_[c] ? 0 : 1);
    for (std::uint32_t p = 0; p < pairs; ++p) {
      const std::uint32_t ia = first + p, ib = first + (p + 1) % (last - first);
      const ChainNode& a = chain_[ia];
      const ChainNode& b = chain_[ib];
      if (a.side != 0 && b.side != 0 && a.side != b.side) continue;  // would bridge the wound: leave it open
      CollectRun(curve, a, b, ia);
      ZipPairToRun(skin, a, b);
    }
  }
  DropDegenerateTriangles(skin);
}

std::uint32_t SkinCutter::LipEntry(std::uint32_t lip) const {
  return lips_[lip].node != kNoSlot ? lips_[lip].node : (kLipFlag | lip);
}

Eigen::Vector3d SkinCutter::RestOf(const SkinMesh& skin, std::uint32_t entry) const {
  return (entry & kLipFlag) ? lips_[entry & ~kLipFlag].rest_m : Eigen::Vector3d(skin.model.x0_m.col(entry));
}

// The run of wound nodes from a's to b's (run_): their own, and between them
// every shared parameter strictly inside their matches, on their side.
void SkinCutter::CollectRun(const IncisionCurve& curve, const ChainNode& a, const ChainNode& b, std::uint32_t ia) {
  run_.clear();
  run_.push_back(LipEntry(a.lip));
  const int side = a.side != 0 ? a.side : b.side;
  if (side != 0) {
    const double lo = std::min(a.s, b.s), hi = std::max(a.s, b.s);
    for (std::size_t m = 0; m < params_.size(); ++m) {
      const std::size_t k = side > 0 ? m : params_.size() - 1 - m;  // the left run climbs, the right descends
      if (params_[k] > lo + 1e-12 && params_[k] < hi - 1e-12) run_.push_back(LipEntry(SideLip(curve, side, k, ia)));
    }
  }
  run_.push_back(LipEntry(b.lip));
}

// Sound: a positive area and no other border node inside (a notch in the
// hole's border must not be covered) — repeats make no triangle.
bool SkinCutter::SoundTriangle(const SkinMesh& skin, std::uint32_t x, std::uint32_t y, std::uint32_t z) const {
  if (x == y || y == z || x == z) return true;
  const Eigen::Vector3d px = RestOf(skin, x), py = RestOf(skin, y), pz = RestOf(skin, z);
  if (!(SignedArea2D(px, py, pz) > 0.0)) return false;
  for (const ChainNode& other : chain_) {
    if (other.node == x || other.node == y || other.node == z) continue;
    const Eigen::Vector3d q = skin.model.x0_m.col(other.node);
    if (SignedArea2D(px, py, q) > 0.0 && SignedArea2D(py, pz, q) > 0.0 && SignedArea2D(pz, px, q) > 0.0) return false;
  }
  return true;
}

void SkinCutter::EmitTriangle(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
  if (x != y && y != z && x != z) new_triangles_.push_back({x, y, z});
}

// Zip: polygon b, a, run[0..n], counter-clockwise. From a the run is
// followed while the shorter diagonal says so; then b fans over the rest.
// A step is taken only if its triangles keep a positive area (on a bending
// curve the shorter diagonal can fold the fan).
void SkinCutter::ZipPairToRun(const SkinMesh& skin, const ChainNode& a, const ChainNode& b) {
  const std::size_t n = run_.size() - 1;
  fan_ok_.assign(n + 1, 1);  // fan_ok_[j]: b's fan over run[j..n] keeps a positive area
  for (std::size_t j = n; j-- > 0;) fan_ok_[j] = fan_ok_[j + 1] && SoundTriangle(skin, b.node, run_[j], run_[j + 1]);
  std::size_t j = 0;
  while (j < n) {
    const bool advance = SoundTriangle(skin, a.node, run_[j], run_[j + 1]);
    const bool turn = SoundTriangle(skin, b.node, a.node, run_[j]) && fan_ok_[j];
    const bool shorter = (RestOf(skin, a.node) - RestOf(skin, run_[j + 1])).squaredNorm() <=
                         (RestOf(skin, b.node) - RestOf(skin, run_[j])).squaredNorm();
    if (advance && (!turn || shorter)) {
      EmitTriangle(a.node, run_[j], run_[j + 1]);
      ++j;
    } else {
      break;  // b takes over (if neither step is sound, the check below drops what folds)
    }
  }
  // What is not sound is left open (counted): a gap, never an overlap.
  auto emit_sound = [&](std::uint32_t x, std::uint32_t y, std::uint32_t z) {
    if (SoundTriangle(skin, x, y, z)) {
      EmitTriangle(x, y, z);
    } else {
      ++planned_skips_;
    }
  };
  emit_sound(b.node, a.node, run_[j]);
  for (; j < n; ++j) emit_sound(b.node, run_[j], run_[j + 1]);
}

// Drops what would be inverted or degenerate at rest (counted by the caller).
void SkinCutter::DropDegenerateTriangles(const SkinMesh& skin) {
  const double min_area = 1e-6 * skin.def.spacing_m * skin.def.spacing_m;
  planned_skips_ += static_cast<std::uint32_t>(std::erase_if(new_triangles_, [&](const Tri& t) {
    return !(SignedArea2D(RestOf(skin, t[0]), RestOf(skin, t[1]), RestOf(skin, t[2])) > min_area);
  }));
}

CutStats SkinCutter::CutAlongLastSegment(SkinMesh& skin, const IncisionCurve& curve, const CutConfig& config) {
  CutStats st;
  config_ = config;
  if (curve.Segments() < 1) return st;
  SampleLastSegment(skin, curve);
  FindSweptTriangles(skin);
  if (removed_triangles_.empty()) return st;  // the blade moved through a hole already cut
  const bool planned = !LinkHoleBorder(skin.topology) && PlanChains(skin, curve);
  for (auto& c : chain_) has_prev_[c.node] = 0;  // the walk's visited marks
  if (!planned) return Refused(st);
  PlanTriangles(skin, curve);
  st.skipped_triangles = planned_skips_;
  if (!FitsCapacities(skin)) return Refused(st);
  // Nothing changed so far; from here the cut is applied whole.
  touched_.clear();
  RemoveSweptVolume(skin, st);
  RemoveSpringsAcrossZone(skin, st);
  AddWoundTriangles(skin, st);
  UpdateAroundCut(skin);
  ClearCutScratch();
  return st;
}

// The curve's last segment as a polyline on the rest plane, its box, and
// how far the distance queries reach.
void SkinCutter::SampleLastSegment(const SkinMesh& skin, const IncisionCurve& curve) {
  const int k = curve.Segments() - 1;
  polyline_.clear();
  for (int i = 0; i < kPolylineSamples; ++i) {
    const Eigen::Vector2d p = BezierPoint(curve.Controls(k), static_cast<double>(i) / (kPolylineSamples - 1));
    polyline_.emplace_back(p.x(), p.y(), 0.0);
  }
  zone_radius_m_ = config_.sweep_radius_m;
  polyline_lo_ = polyline_hi_ = polyline_.front().head<2>();
  for (const Eigen::Vector3d& p : polyline_)
    polyline_lo_ = polyline_lo_.cwiseMin(p.head<2>()), polyline_hi_ = polyline_hi_.cwiseMax(p.head<2>());
  far_m_ = zone_radius_m_ + 2.5 * skin.def.spacing_m;  // the widest reach any caller asks about
}

// Stage 1: the swept volume's nodes (inside_) and their triangles
// (removed_triangles_, marked in triangle_mark_).
void SkinCutter::FindSweptTriangles(const SkinMesh& skin) {
  const MeshTopology& topo = skin.topology;
  inside_.clear();
  for (std::uint32_t v = 0; v < topo.Vertices().HighWater(); ++v) {
    // Skin nodes only (other vertex slots, e.g. a tool's, have no live node).
    if (topo.Vertices().IsLive(v) && skin.model.node_live[v] && DistanceToSegment(skin.model.x0_m.col(v)) < zone_radius_m_)
      inside_.push_back(v);
  }
  removed_triangles_.clear();
  for (const std::uint32_t v : inside_)
    for (const std::uint32_t t : topo.TrianglesOf(v))
      if (!triangle_mark_[t]) {
        triangle_mark_[t] = 1;
        removed_triangles_.push_back(t);
      }
}

// The hole's border: edges of surviving triangles that faced a removed one,
// oriented with the hole on their right (b -> a for a removed a -> b), as
// next_ links. True if the hole touches itself at a node (pinched).
bool SkinCutter::LinkHoleBorder(const MeshTopology& topo) {
  bool pinched = false;
  for (const std::uint32_t t : removed_triangles_) {
    const auto& tv = topo.TriangleVertices(t);
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t a = tv[static_cast<std::size_t>(e)], b = tv[static_cast<std::size_t>((e + 1) % 3)];
      const std::uint32_t twin = topo.TriangleWithEdge(b, a);
      if (twin == kNoSlot || triangle_mark_[twin]) continue;
      if (next_[b] != kNoSlot) pinched = true;  // the hole touches itself at b
      if (next_[b] == kNoSlot) border_nodes_.push_back(b);
      next_[b] = a;
      has_prev_[a] = 1;
    }
  }
  return pinched;
}

// The scratch marks and border links back to empty for the next cut.
void SkinCutter::ClearCutScratch() {
  for (const std::uint32_t t : removed_triangles_) triangle_mark_[t] = 0;
  for (const std::uint32_t b : border_nodes_) {
    has_prev_[next_[b]] = 0;
    has_prev_[b] = 0;
    next_[b] = kNoSlot;
  }
  border_nodes_.clear();
}

CutStats SkinCutter::Refused(CutStats st) {
  ClearCutScratch();
  st.refused = true;
  return st;
}

// Capacities, conservatively (before anything is freed): a cut that might
// not fit is refused whole rather than left half done.
bool SkinCutter::FitsCapacities(const SkinMesh& skin) const {
  const MeshTopology& topo = skin.topology;
  std::size_t new_nodes = 0;
  for (const Lip& l : lips_) new_nodes += l.node == kNoSlot;
  const std::size_t free_vertices = topo.Vertices().Capacity() - topo.Vertices().LiveCount();
  const std::size_t free_triangles = topo.Triangles().Capacity() - topo.Triangles().LiveCount() + removed_triangles_.size();
  const std::size_t free_springs = static_cast<std::size_t>(skin.model.spring_capacity - skin.model.NumSprings());
  return !(new_nodes > free_vertices || new_triangles_.size() > free_triangles ||
           3 * new_triangles_.size() > free_springs);
}

void SkinCutter::Touch(std::uint32_t v) {
  if (!touched_mark_[v]) {
    touched_mark_[v] = 1;
    touched_.push_back(v);
  }
}

// Applies stage 1: the swept triangles, then the nodes nothing uses any
// more (their springs go with them).
void SkinCutter::RemoveSweptVolume(SkinMesh& skin, CutStats& st) {
  MeshTopology& topo = skin.topology;
  for (const std::uint32_t t : removed_triangles_) {
    for (const std::uint32_t v : topo.TriangleVertices(t)) Touch(v);
    topo.RemoveTriangle(t);
    ++st.triangles_removed;
  }
  for (const std::uint32_t v : touched_) {
    if (topo.VertexUses(v) != 0) continue;
    st.springs_removed += static_cast<std::uint32_t>(skin.model.DegreeOf(static_cast<std::int32_t>(v)));
    DeactivateNode(skin.model, skin.state, static_cast<std::int32_t>(v));
    topo.RemoveVertex(v);
    skin.on_lip[v] = 0;
    ++st.nodes_removed;
  }
  // Before any slot is reused by a new wound node (else a reused slot would
  // be listed twice and its wound faces pulled twice).
  std::erase_if(skin.lip_nodes, [&](std::uint32_t v) { return !topo.Vertices().IsLive(v); });
}

// Springs of nodes near the zone whose rest segment crosses it and that
// are not an edge of a surviving triangle (shear and bending springs
// across the cut). Spring indices move on removal: look each up again.
void SkinCutter::RemoveSpringsAcrossZone(SkinMesh& skin, CutStats& st) {
  const MeshTopology& topo = skin.topology;
  const double reach = far_m_;
  for (std::uint32_t v = 0; v < topo.Vertices().HighWater(); ++v) {
    if (!skin.model.node_live[v] || DistanceToSegment(skin.model.x0_m.col(v)) > reach) continue;
    for (std::int32_t e = 0; e < skin.model.DegreeOf(static_cast<std::int32_t>(v));) {
      const auto s = static_cast<std::size_t>(skin.model.SpringsOf(static_cast<std::int32_t>(v))[e]);
      const std::uint32_t i = static_cast<std::uint32_t>(skin.model.spring_i[s]), j = static_cast<std::uint32_t>(skin.model.spring_j[s]);
      const bool edge = topo.TriangleWithEdge(i, j) != kNoSlot || topo.TriangleWithEdge(j, i) != kNoSlot;
      if (!edge && SegmentCrossesZone(skin.model.x0_m.col(i), skin.model.x0_m.col(j))) {
        RemoveSpring(skin.model, static_cast<std::int32_t>(s));
        ++st.springs_removed;
      } else {
        ++e;
      }
    }
  }
}

// Applies stage 3: the planned triangles, each with its edge springs.
void SkinCutter::AddWoundTriangles(SkinMesh& skin, CutStats& st) {
  lip_nodes_.assign(lips_.size(), kNoSlot);
  new_springs_.clear();
  for (Tri t : new_triangles_) {
    for (auto& e : t) e = WoundNode(skin, e, st);
    if (skin.topology.AddTriangle(t[0], t[1], t[2], kWoundPart) == kNoSlot) {
      ++st.skipped_triangles;
      continue;
    }
    ++st.triangles_added;
    AddEdgeSprings(skin, t, st);
  }
}

// The node a planned triangle's entry stands for. A wound node is made when
// a triangle first uses one: rest on the curve, displaced like the border
// node it was matched from.
std::uint32_t SkinCutter::WoundNode(SkinMesh& skin, std::uint32_t entry, CutStats& st) {
  if (!(entry & kLipFlag)) return entry;
  const std::uint32_t lip = entry & ~kLipFlag;
  if (lip_nodes_[lip] != kNoSlot) return lip_nodes_[lip];
  const Lip& l = lips_[lip];
  const std::uint32_t v = skin.topology.AddVertex();  // capacity checked (FitsCapacities)
  const std::uint32_t from = chain_[l.from_chain].node;
  NodeDef def;
  def.x_W_m = l.rest_m;
  def.mass_kg = skin.model.mass_kg[static_cast<Eigen::Index>(from)];  // re-lumped in UpdateAroundCut
  def.damping_Ns_per_m = skin.def.node_damping_Ns_per_m;
  def.anchor_k_N_per_m = config_.wound_anchor_k_N_per_m;
  ActivateNode(skin.model, skin.state, static_cast<std::int32_t>(v), def);
  skin.state.x_m.col(v) = skin.state.x_m.col(from) + (l.rest_m - skin.model.x0_m.col(from));
  skin.state.v_m_per_s.col(v) = skin.state.v_m_per_s.col(from);
  skin.on_lip[v] = 1;
  skin.lip_nodes.push_back(v);
  Touch(v);
  ++st.nodes_added;
  return lip_nodes_[lip] = v;
}

// A spring on each edge of a new triangle that has none yet (rest length
// from the rest plane, pre-strained like the skin's).
void SkinCutter::AddEdgeSprings(SkinMesh& skin, const Tri& t, CutStats& st) {
  for (int e = 0; e < 3; ++e) {
    const auto a = static_cast<std::int32_t>(t[static_cast<std::size_t>(e)]);
    const auto b = static_cast<std::int32_t>(t[static_cast<std::size_t>((e + 1) % 3)]);
    Touch(static_cast<std::uint32_t>(a));
    if (FindSpring(skin.model, a, b) != kNoSpring) continue;
    const double rest = (skin.model.x0_m.col(a) - skin.model.x0_m.col(b)).norm() * (1.0 - skin.def.prestrain);
    if (AddSpring(skin.model, a, b, rest, skin.def.spring_k_N_per_m, skin.def.spring_c_Ns_per_m) != kNoSpring) {
      new_springs_.push_back({static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b)});
      ++st.springs_added;
    } else {
      ++st.springs_refused;
    }
  }
}

// What the cut changed around it: the touched nodes' masses re-lumped, the
// new springs' stiffness, the wound's edges and the pre-stress hold.
void SkinCutter::UpdateAroundCut(SkinMesh& skin) {
  for (const std::uint32_t v : touched_) {
    if (skin.topology.Vertices().IsLive(v)) RelumpNodeMass(skin, v);
    touched_mark_[v] = 0;
  }
  SetNewSpringStiffness(skin);
  RebuildWoundEdges(skin);
  // Every spring this cut removed, added or stiffened had an end within
  // reach of the segment: the pre-stress's hold changed only there.
  for (std::uint32_t v = 0; v < skin.topology.Vertices().HighWater(); ++v)
    if (skin.model.node_live[v] && DistanceToSegment(skin.model.x0_m.col(v)) <= far_m_) UpdatePrestressHoldOf(skin, v);
}

// The new triangles replace lattice that had two-apart springs besides its
// edges; edge springs of K alone would leave a band along the wound a third
// softer along it (the wound then gapes ~10 % too wide). Each new edge gets
// van Gelder's membrane stiffness instead (Approximate simulation of elastic
// membranes by triangulated spring meshes, 1998): k = E t sum over its
// triangles of A / |e|^2, exact for equilateral triangles, with this
// lattice's E t = 8 K / 3.
void SkinCutter::SetNewSpringStiffness(SkinMesh& skin) const {
  const double et_N_per_m = 8.0 * skin.def.spring_k_N_per_m / 3.0;
  for (const auto& [a, b] : new_springs_) {
    double area_per_length2 = 0.0;
    const Eigen::Vector3d pa = skin.model.x0_m.col(a), pb = skin.model.x0_m.col(b);
    for (const std::uint32_t t : skin.topology.TrianglesOf(a)) {
      const auto& v = skin.topology.TriangleVertices(t);
      if (v[0] != b && v[1] != b && v[2] != b) continue;
      const Eigen::Vector3d p0 = skin.model.x0_m.col(v[0]), p1 = skin.model.x0_m.col(v[1]),
                            p2 = skin.model.x0_m.col(v[2]);
      area_per_length2 += 0.5 * std::abs((p1 - p0).cross(p2 - p0).z()) / (pb - pa).squaredNorm();
    }
    const std::int32_t s = FindSpring(skin.model, static_cast<std::int32_t>(a), static_cast<std::int32_t>(b));
    if (s != kNoSpring && area_per_length2 > 0.0)
      skin.model.spring_k_N_per_m[static_cast<std::size_t>(s)] = et_N_per_m * area_per_length2;
  }
}

void SkinCutter::RebuildWoundEdges(SkinMesh& skin) {
  skin.wound_edges.clear();
  const MeshTopology& topo = skin.topology;
  for (const std::uint32_t v : skin.lip_nodes) {
    for (const std::uint32_t t : topo.TrianglesOf(v)) {
      const auto& tv = topo.TriangleVertices(t);
      for (int e = 0; e < 3; ++e) {
        if (tv[static_cast<std::size_t>(e)] != v) continue;
        const std::uint32_t w = tv[static_cast<std::size_t>((e + 1) % 3)];
        if (topo.TriangleWithEdge(w, v) == kNoSlot && !(skin.on_border[v] && skin.on_border[w]) &&
            skin.wound_edges.size() < skin.wound_edges.capacity()) {
          skin.wound_edges.push_back({v, w});
        }
      }
    }
  }
}

}  // namespace hapsim::core
