// The cutting paper's three-stage cut (§2.3), run on the skin's rest plane
// each time the blade has advanced by one incision segment:
//
//  1. Swept volume: every triangle with a node within sweep_radius of the
//     new segment goes, with the nodes left unused and every spring whose
//     rest segment crosses that zone (the "incision generation area").
//  2. Bézier incision: the segment has just been appended to the incision
//     curve (incision_curve.h), through the blade's positions.
//  3. Shortest-distance node matching: each node on the hole's border is
//     matched to its closest point on the curve, where a wound node is
//     placed (one lip of the incision on each side; the nodes matched to
//     the curve's ends share its end node — the paper's "yellow" nodes).
//     Border node, match, next border node and its match make a
//     quadrilateral split by its shorter diagonal (the "blue" nodes'
//     quadrilaterals); a border node already on the curve (a lip from the
//     previous segment) closes a triangle instead. The hole is filled
//     exactly: the two lips coincide at rest, so the patch's rest area is
//     unchanged, and residual stress (skin_mesh.h) then opens the wound.
//
// [decide] The paper does not say how the wound's two sides stay apart if
// both are matched to the same curve: here each side gets its own lip nodes
// on the curve, joined only at the incision's ends.
//
// New triangles get edge springs (K, rest length from the rest plane), new
// nodes an anchor and a mass lumped from their triangles; the touched nodes
// are re-lumped, so total mass = density x area before and after. Nothing
// allocates: scratch is reserved at construction. A commit that would need
// more than the capacities, or that meets a configuration it cannot fill
// (a hole pinched at a node, a triangle that would be inverted), changes
// nothing or skips that triangle, and is counted — never a crash.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "hapsim/core/cutting/incision_curve.h"
#include "hapsim/core/cutting/skin_mesh.h"

namespace hapsim::core {

struct CutConfig {
  double sweep_radius_m = 0.001;       // stage 1's swept disc radius
  double wound_anchor_k_N_per_m = 1.0; // anchor of the nodes a cut adds
};

struct CutStats {
  std::uint32_t triangles_removed = 0, triangles_added = 0;
  std::uint32_t nodes_removed = 0, nodes_added = 0;
  std::uint32_t springs_removed = 0, springs_added = 0;
  std::uint32_t skipped_triangles = 0;  // would have been inverted or degenerate
  std::uint32_t springs_refused = 0;    // an edge spring a full node (max_node_degree) or the spring capacity refused
  bool refused = false;                 // nothing changed: capacity or an unfillable hole
  CutStats& operator+=(const CutStats& o);
};

class SkinCutter {
 public:
  SkinCutter() = default;
  explicit SkinCutter(const SkinMesh& skin);  // reserves the scratch for this skin's capacities

  // Cuts along the curve's last segment (just appended). first_segment: it
  // starts the incision (no wound behind it yet).
  CutStats CutAlongLastSegment(SkinMesh& skin, const IncisionCurve& curve, const CutConfig& config);

  // Rebuilds skin.wound_edges from the lip nodes (after a cut or a reset).
  static void RebuildWoundEdges(SkinMesh& skin);

 private:
  // Van Gelder's stiffness for the springs this cut added (new_springs_).
  void SetNewSpringStiffness(SkinMesh& skin) const;
  struct ChainNode {
    std::uint32_t node = 0;
    double s = 0.0;        // curve parameter of its match
    int side = 0;          // +1 left, -1 right, 0 on the curve or at an end
    std::uint32_t lip = kNoSlot;  // index into lips_ (its matched wound node)
  };
  struct Lip {
    Eigen::Vector3d rest_m;
    std::uint32_t from_chain = 0;    // chain entry whose displacement it takes
    std::uint32_t node = kNoSlot;    // existing node (a border node on the curve) or kNoSlot: new
  };
  using Tri = std::array<std::uint32_t, 3>;  // entries: node | kLipFlag + lip index

  // Rest-plane distance to the sampled segment (beyond far_m_: a lower bound).
  double DistanceToSegment(const Eigen::Vector3d& p) const;
  bool SegmentCrossesZone(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const;

  // CutAlongLastSegment's steps, in order.
  void SampleLastSegment(const SkinMesh& skin, const IncisionCurve& curve);
  void FindSweptTriangles(const SkinMesh& skin);
  bool LinkHoleBorder(const MeshTopology& topo);  // true: the hole is pinched
  bool PlanChains(const SkinMesh& skin, const IncisionCurve& curve);
  void PlanTriangles(const SkinMesh& skin, const IncisionCurve& curve);
  bool FitsCapacities(const SkinMesh& skin) const;
  void RemoveSweptVolume(SkinMesh& skin, CutStats& st);
  void RemoveSpringsAcrossZone(SkinMesh& skin, CutStats& st);
  void AddWoundTriangles(SkinMesh& skin, CutStats& st);
  void UpdateAroundCut(SkinMesh& skin);
  void ClearCutScratch();
  CutStats Refused(CutStats st);  // scratch cleared, st marked refused
  void Touch(std::uint32_t v);    // v's mass is re-lumped after the cut
  std::uint32_t WoundNode(SkinMesh& skin, std::uint32_t entry, CutStats& st);
  void AddEdgeSprings(SkinMesh& skin, const Tri& t, CutStats& st);

  // PlanChains' steps, in order.
  bool WalkChain(std::uint32_t start, bool closed);
  bool WalkBorderChains();
  void MatchBorderToCurve(const SkinMesh& skin, const IncisionCurve& curve);
  void StartLoopAtCurveStart();
  void KeepMatchesFromFolding(double end_s);
  void PlaceCurveLips(const SkinMesh& skin, const IncisionCurve& curve);
  void CollectSharedParams(const SkinMesh& skin, const IncisionCurve& curve);
  void MergeCloseParams(const SkinMesh& skin, const IncisionCurve& curve);
  void SnapSideMatches();
  void AssignOldLipSides(std::size_t chain, double end_s);
  void LinkSideNodes(const IncisionCurve& curve, std::size_t chain);
  // The chain entry step places from entry i of chain (nullptr past an open chain's ends).
  const ChainNode* ChainNeighbour(std::size_t chain, std::uint32_t i, int step) const;
  bool IsOwnLip(const ChainNode& n) const;  // a border node on the curve: its own wound node

  // PlanTriangles' steps.
  std::uint32_t LipEntry(std::uint32_t lip) const;  // a Tri entry for lips_[lip]
  Eigen::Vector3d RestOf(const SkinMesh& skin, std::uint32_t entry) const;
  void CollectRun(const IncisionCurve& curve, const ChainNode& a, const ChainNode& b, std::uint32_t ia);
  bool SoundTriangle(const SkinMesh& skin, std::uint32_t x, std::uint32_t y, std::uint32_t z) const;
  void EmitTriangle(std::uint32_t x, std::uint32_t y, std::uint32_t z);
  void ZipPairToRun(const SkinMesh& skin, const ChainNode& a, const ChainNode& b);
  void DropDegenerateTriangles(const SkinMesh& skin);

  std::size_t ParamIndex(double s) const;  // of the shared parameter s
  // The wound node on `side` at shared parameter k (created on first use).
  std::uint32_t SideLip(const IncisionCurve& curve, int side, std::size_t k, std::uint32_t from_chain);

  CutConfig config_;
  std::vector<Eigen::Vector3d> polyline_;           // the segment sampled (rest plane)
  double zone_radius_m_ = 0.0;
  Eigen::Vector2d polyline_lo_ = Eigen::Vector2d::Zero(), polyline_hi_ = Eigen::Vector2d::Zero();  // its box
  double far_m_ = 0.0;  // beyond this from the box, DistanceToSegment returns the box distance
  std::vector<std::uint32_t> inside_;               // nodes within the sweep radius
  std::vector<std::uint32_t> removed_triangles_;
  std::vector<std::uint8_t> triangle_mark_;         // (triangle capacity)
  std::vector<std::uint32_t> next_;                 // (vertex capacity) hole border: next node, kNoSlot none
  std::vector<std::uint8_t> has_prev_;              // (vertex capacity)
  std::vector<std::uint32_t> border_nodes_;         // nodes with a next_ entry (to reset)
  std::vector<ChainNode> chain_;                    // all chains, back to back
  std::vector<std::uint32_t> chain_start_;          // chain k: chain_[chain_start_[k], chain_start_[k+1])
  std::vector<std::uint8_t> chain_closed_;
  std::vector<Lip> lips_;
  std::vector<double> params_;                      // matches of both sides, sorted, unique
  std::vector<std::uint32_t> left_lips_, right_lips_;  // lips_ index per params_ entry, kNoSlot until made
  std::vector<std::uint32_t> run_;                  // one border pair's wound nodes
  std::vector<std::uint8_t> fan_ok_;
  std::vector<Tri> new_triangles_;
  std::vector<std::uint32_t> lip_nodes_;            // lips_ -> node slots, once created
  std::vector<std::uint32_t> touched_;              // nodes to re-lump
  std::vector<std::array<std::uint32_t, 2>> new_springs_;  // edges this cut gave a spring
  std::vector<std::uint8_t> touched_mark_;          // (vertex capacity)
  std::uint32_t planned_skips_ = 0;
};

}  // namespace hapsim::core
