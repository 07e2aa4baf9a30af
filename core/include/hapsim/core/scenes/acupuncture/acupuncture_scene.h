// acupuncture: the acupuncture paper's model (three SHF tissue layers under a
// mass-spring force net, CMC 2021) as a Scene.
//
// Tissue: a limb-like body part (shf/limb_segment.h) whose skin top is at the
// world origin (outward normal +z, tissue below). Four nested star-shaped SH
// surfaces fitted from it share one centre: skin top, fat top (0.8 mm
// down), muscle top (9.2 mm) and muscle bottom (48.2 mm), radial offsets.
// The tip's radial depth below each surface (one SH basis evaluation per
// tick) drives the layered puncture:
//
//   free ──tip reaches layer ℓ's surface──▶ pressing ℓ: force net placed at
//   the contact point N1, N1 follows the tip, F = net reaction (eq. 6)
//   pressing ℓ ──Z_w >= ζ──▶ puncture ℓ (event): virtual springs removed,
//   the net springs back by shape matching, the tip is inside layer ℓ
//   inside ℓ ──tip reaches layer ℓ+1's surface──▶ pressing ℓ+1
//   withdrawal: leaving a layer's top moves back up one layer; leaving the
//   skin ends contact. [decide] A withdrawn needle leaves no hole: the next
//   insertion punctures the skin again.
//
// Force on the tool: net reaction while pressing, plus Table 1 shaft damping
// −b (v·a) a with b = Σ d_i h_i over the pierced layers and a the insertion
// axis at skin puncture, plus a lateral "tunnel" spring towards that axis.
// [decide] Layers do not carry each other: a press on one surface does not
// move the surfaces below (the dimple Z_1* is far smaller than the layer).
//
// ForceModel(): free → kFree; pressing the skin → kContact with the normal at
// N1, stiffness = the net's tangent stiffness K Σ g (capped for the device),
// anchor chosen so the law reproduces the physics force at the current tip;
// after skin puncture → kPunctured (tunnel: lateral spring to the entry axis,
// axial damping b, stick-slip shaft friction, and a deeper layer being
// pressed as a half-space across the axis with its net's tangent stiffness,
// the rest of its push fed forward). EvaluateLocalForce at the current tip
// and velocity reproduces ToolForce_W_N().
//
// Mesh: three square patches of the skin/fat/muscle surfaces around the
// site (radially displaced by their nets) and a needle, parts "skin", "fat",
// "muscle", "needle". Topology never changes. Reset() also puts the needle
// back to its initial pose (tip 5 cm above the skin, pointing down).
#pragma once
#include <array>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hapsim/core/needle/force_net.h"
#include "hapsim/core/scenes/acupuncture/acupuncture_params.h"
#include "hapsim/core/scenes/scene.h"
#include "hapsim/core/scenes/scene_outputs.h"
#include "hapsim/core/shf/layered_sh_body.h"

namespace hapsim::core {

class AcupunctureScene final : public SceneWithOutputs {
 public:
  explicit AcupunctureScene(const AcupunctureParams& params);

  std::string_view Name() const override { return "acupuncture"; }
  void Step(const ToolInput& tool, double dt_s) override;
  void Reset() override;
  double SimTime_s() const override { return t_s_; }
  const Eigen::Matrix3Xd& Vertices_m() const override { return vertices_m_; }
  const MeshTopology& Topology() const override { return topology_; }
  std::uint64_t StateHash() const override;
  std::unique_ptr<const Scene> SaveState() const override { return std::make_unique<const AcupunctureScene>(*this); }
  void RestoreState(const Scene& saved) override { AssignSavedState(*this, saved); }

  // Diagnostics for validation and tests.
  const AcupunctureParams& Params() const { return params_; }
  const ForceNetModel& Net(int layer) const { return nets_.at(static_cast<std::size_t>(layer)); }
  const ForceNetState& NetState(int layer) const { return net_states_.at(static_cast<std::size_t>(layer)); }
  const Eigen::VectorXd& SpringbackEta(int layer) const { return eta_.at(static_cast<std::size_t>(layer)); }
  int PuncturedLayers() const { return punctured_; }
  bool Pressing() const { return pressing_; }
  // Height of layer's puncture point (net node N1) above the needle tip at
  // the puncture instant, along the outward normal [m]; nullopt before puncture.
  std::optional<double> PuncturePointOffset_m(int layer) const;
  double ShaftDamping_Ns_per_m() const { return shaft_damping_Ns_per_m_; }
  double ShaftCoulomb_N() const { return shaft_coulomb_N_; }
  LayeredShBody& Body() { return body_; }

 private:
  void ResetState();
  void NumericalReset();
  // Step: the needle leaves the tissue (LoseTool) or follows the tool, then
  // the nets spring back and the blow-up guard checks what is published.
  void LoseTool(const ToolInput& tool);
  void FollowTool(const ToolInput& tool);  // UpdateInsertion, ComputeForce, ComputeForceModel
  void AdvanceSpringback();
  bool PublishedStateFinite() const;
  void UpdateInsertion(const Eigen::Vector3d& tip, const Eigen::Vector3d& axis);
  void StartContact(int layer, const Eigen::Vector3d& tip);
  void Puncture(int layer, const Eigen::Vector3d& tip, const Eigen::Vector3d& axis);
  void ComputeForce(const Eigen::Vector3d& tip, const Eigen::Vector3d& v);
  void ComputeForceModel(const Eigen::Vector3d& tip, const Eigen::Vector3d& v);
  double RenderedNetStiffness_N_per_m(std::size_t layer) const;        // capped for the device
  double DepthToPuncture_m(std::size_t layer) const;                   // deeper press left before it gives
  LocalForceModel TunnelForceModel(const Eigen::Vector3d& tip) const;  // after skin puncture
  LocalForceModel SkinPressForceModel(const Eigen::Vector3d& tip, const Eigen::Vector3d& v) const;
  void BuildDisplay();
  void PlacePatchVertices(int layer);  // at build: one layer's patch_rest_W_m_ and patch_dir_W_
  void ShowNet(int layer);   // the patch follows this layer's freshly placed net
  void HideNet(int layer);   // the patch goes back to rest
  void UpdatePatches();
  void UpdateNeedleMesh(const Eigen::Vector3d& tip, const Eigen::Vector3d& axis);
  void Log(SceneEventKind kind, int layer, const Eigen::Vector3d& where);

  AcupunctureParams params_;
  LayeredShBody body_;
  std::array<ForceNetModel, kNumTissueLayers> nets_;
  std::array<ForceNetState, kNumTissueLayers> net_states_;
  std::array<Eigen::VectorXd, kNumTissueLayers> eta_;       // springback factor per particle
  std::array<Eigen::VectorXd, kNumTissueLayers> unit_mass_;  // shape-matching masses (equal)
  std::array<bool, kNumTissueLayers> net_shown_{};           // net deforms the displayed patch
  std::array<bool, kNumTissueLayers> net_moved_{};           // net particles moved this tick
  std::array<bool, kNumTissueLayers> springing_back_{};      // shape matching still running
  std::array<Eigen::Vector3d, kNumTissueLayers> puncture_tip_W_m_;
  std::array<bool, kNumTissueLayers> punctured_once_{};

  // Insertion state.
  bool pressing_ = false;  // pressing the surface of layer punctured_
  int punctured_ = 0;      // surfaces pierced along the current insertion (0..3)
  Eigen::Vector3d entry_W_m_ = Eigen::Vector3d::Zero();      // skin puncture point
  Eigen::Vector3d entry_axis_W_ = -Eigen::Vector3d::UnitZ();  // insertion direction at skin puncture
  Eigen::VectorXd depth_m_;  // tip depth below each SH surface (4)
  double shaft_damping_Ns_per_m_ = 0.0;
  double shaft_coulomb_N_ = 0.0;                 // Coulomb level of the shaft friction now (law 1)
  Eigen::Vector3d stick_W_m_ = Eigen::Vector3d::Zero();  // where the shaft sticks (law 1)

  double t_s_ = 0.0;

  // Display.
  int patch_vertices_ = 0;           // per layer
  Eigen::Matrix3Xd patch_rest_W_m_;  // rest vertices of the three patches (3 x 3·G²)
  Eigen::Matrix3Xd patch_dir_W_;     // unit radial direction per patch vertex
  // Patch vertices within reach of each layer's placed net (capacity G²,
  // filled when the net is placed): only these are ever displaced.
  std::array<std::vector<std::int32_t>, kNumTissueLayers> patch_near_net_;
  // Their in-plane distance from N1 in spring lengths (ring coordinate q),
  // fixed while the net stays placed.
  std::array<std::vector<double>, kNumTissueLayers> patch_near_q_;
  Eigen::Matrix3Xd vertices_m_;
  MeshTopology topology_;
};

// MakeAcupunctureScene(params) is declared in scene_builders.h.

}  // namespace hapsim::core
