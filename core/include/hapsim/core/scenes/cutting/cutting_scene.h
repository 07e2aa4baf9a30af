// cutting: the cutting paper's scalpel incision on skin (mass-spring skin with
// residual stress, three-stage cut) as a Scene. Skin: cutting/skin_mesh.h
// (a 60 x 40 mm mass-spring patch, anchored underneath, the paper's Table 1).
// The scalpel is a cylinder from the tool tip along the tool (paper §2.2); its
// collisions are found by the paper's two-angle + distance test behind a grid
// broad phase.
//
//   free ──tip below the surface── pressing: the tip-skin penalty pushes the
//     tool up (reaction on the nodes under the tip), nodes inside the blade
//     cylinder are pushed out from its axis (the paper's force "from N along
//     N -> p"); kContact.
//   pressing ──tip deeper than cut_depth_m── cutting (event cut_start): the
//     blade's crossing of the skin plane starts the incision curve; each
//     segment_length_m of travel commits a segment (three-stage cut,
//     cutting/skin_cutter.h); the tool feels kCutting: a drag along the
//     incision (cut_force_N, smoothed Coulomb, plus cut_damping_Ns_per_m),
//     and the pressing law against going deeper (k and b from the rest
//     surface z = 0, carried by the tissue underneath). The blade's sides
//     push only the wound's lips, across the incision into their tissue.
//   cutting ──tip above the surface, off the patch, or the tool gone──
//     free (event cut_end, value = the incision's length).
//
// One material: the springs are the membrane of E and t (skin_mesh.h), and
// the skin carries sigma_r = E eps_r as a uniform pre-stress, balanced where
// it lies; a cut frees the wound's faces of it (ApplyResidualStress gives
// them the released traction every tick), so the wound gapes while the
// lips keep their tension along the cut. Node masses are lumped from an
// areal density with interior nodes of node_mass_kg (docs/validation.md).
//
// Mesh: vertex slot = MSM node (skin and the nodes cuts add), plus eight
// fixed slots for the blade; parts "skin", "wound" (triangles a cut made),
// "blade". [decide] The skin plane z = 0 is the surface for the cut depth
// (the skin moves a millimetre at most under a blade).
#pragma once
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "hapsim/core/cutting/cylinder_collision.h"
#include "hapsim/core/cutting/incision_curve.h"
#include "hapsim/core/cutting/skin_cutter.h"
#include "hapsim/core/cutting/skin_mesh.h"
#include "hapsim/core/msm/msm_step.h"
#include "hapsim/core/msm/resting_nodes.h"
#include "hapsim/core/scenes/cutting/cutting_params.h"
#include "hapsim/core/scenes/scene.h"
#include "hapsim/core/scenes/scene_outputs.h"
#include "hapsim/core/spatial/uniform_grid.h"

namespace hapsim::core {

class CuttingScene final : public SceneWithOutputs {
 public:
  explicit CuttingScene(const CuttingParams& params);  // throws std::invalid_argument on bad params

  std::string_view Name() const override { return "cutting"; }
  void Step(const ToolInput& tool, double dt_s) override;
  void Reset() override;
  double SimTime_s() const override { return skin_.state.t_s; }
  const Eigen::Matrix3Xd& Vertices_m() const override { return skin_.state.x_m; }
  const MeshTopology& Topology() const override { return skin_.topology; }
  std::uint64_t StateHash() const override;
  std::unique_ptr<const Scene> SaveState() const override { return std::make_unique<const CuttingScene>(*this); }
  void RestoreState(const Scene& saved) override { AssignSavedState(*this, saved); }

  // For validation and tests.
  const CuttingParams& Params() const { return params_; }
  const SkinMesh& Skin() const { return skin_; }
  const IncisionCurve& Incision() const { return curve_; }
  bool Cutting() const { return cutting_; }
  const std::vector<std::uint32_t>& CollidingNodes() const { return colliding_; }  // last step, ascending
  const CutStats& CutTotals() const { return cut_totals_; }
  // Skin nodes the last step integrated (all free live nodes with rest_force_N = 0).
  std::int32_t AwakeNodes() const;
  double ResidualStress_Pa() const { return params_.youngs_modulus_Pa * params_.residual_strain; }
  // The blade cylinder for a tool pose.
  Cylinder BladeOf(const ToolInput& tool) const;

 private:
  void AddBladeToMesh();                                  // at build
  void CheckStepIsStable(double min_node_mass_kg) const;  // at build; throws std::invalid_argument
  void StepOnce(const ToolInput& tool, double h_s);
  // StepOnce's steps before the cut and the contact, in order.
  void HoldSkinOnTissue();
  void HoldNode(Eigen::Index node);
  double LargestShiftFromRest_m();
  void ClearStepContact();
  void FindNodesInBlade(const Cylinder& blade);
  void UpdateCut(const ToolInput& tool, const Cylinder& blade);
  void EndCut(const Eigen::Vector3d& where);
  void ApplyContact(const ToolInput& tool, const Cylinder& blade);
  void PushNodesOffBlade(const Cylinder& blade);
  void ResistCuttingDeeper(const ToolInput& tool);
  void PressSkinUnderTip(const ToolInput& tool);
  Eigen::Vector3d IntoTissue(std::uint32_t lip_node) const;
  void UpdateForceModel(const ToolInput& tool);
  void UpdateBladeMesh(const Cylinder& blade);
  StepReport StepSkin(double h_s);
  void Log(SceneEventKind kind, const Eigen::Vector3d& where, double value = 0.0);
  void NumericalReset();

  CuttingParams params_;
  SkinMesh skin_;
  MsmModel initial_model_;  // the skin before any cut (Reset)
  MsmState initial_state_;
  std::vector<std::uint8_t> initial_on_lip_;
  MsmWorkspace workspace_;
  // Resting skin (rest_force_N > 0): woken by contact, by a cut (every
  // unbalanced node after a topology edit) and by awake neighbours.
  RestingNodes resting_;
  std::uint64_t rest_checked_version_ = ~std::uint64_t{0};
  Eigen::AlignedBox3d cut_box_;  // rest positions the cuts since the last step may have unbalanced (empty: none)
  // The last edit's box, judged again once the hold is refreshed (the next step's full hold pass).
  Eigen::AlignedBox3d recut_box_;
  std::uint64_t hold_version_ = ~std::uint64_t{0};  // topology version of the last hold of every node
  // Upper bound of the resting nodes' displacement from rest (exact at each full hold pass).
  double resting_shift_bound_m_ = 0.0;
  SkinCutter cutter_;
  CutConfig cut_config_;
  IncisionCurve curve_;
  // Broad phase: the live nodes' rest positions, rebuilt only when the
  // topology moved (a cut); each tick's query grows by the largest node
  // displacement from rest, found in one pass (cheaper than a rebuild).
  UniformGrid rest_grid_;
  std::uint64_t rest_grid_version_ = ~std::uint64_t{0};
  Eigen::AlignedBox3d skin_box_;  // where the skin can be (rest box grown by 10 mm)
  std::array<std::uint32_t, 8> blade_slots_{};
  std::vector<std::uint32_t> colliding_;
  std::vector<std::uint32_t> loaded_nodes_;  // nodes given contact forces this step
  double cut_normal_N_ = 0.0;                // this step's push against cutting deeper (in outputs_.tool_force_W_N.z())

  bool cutting_ = false;
  bool in_contact_ = false;
  Eigen::Vector2d last_surface_point_ = Eigen::Vector2d::Zero();
  CutStats cut_totals_;
  // StateHash's cache: the digest of the topology-dependent model arrays.
  mutable std::uint64_t digest_version_ = ~std::uint64_t{0};
  mutable std::uint64_t topology_digest_ = 0;
};

}  // namespace hapsim::core
