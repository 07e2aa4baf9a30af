// vessel: a blood vessel's wall pressed by a catheter / probe tip (vascular
// paper; MISSION.md §3; issue 12).
//
// Model, per physics step of h = tick / substeps:
//  1. meshless elastic forces on the wall's nodes (meshless/, Müller et al.
//     2004, explicit), integrated into predicted positions with damping;
//  2. XPBD constraint sweeps (pbd/xpbd.h): the paper's stretching constraints
//     between lattice neighbours (axial, around, across the wall) with
//     compliance 1 / (stretch_fraction E spacing), optionally the paper's
//     per-tetrahedron energy constraints (tet_fraction), and the tip's contact —
//     each node inside the probe sphere is pushed out with compliance
//     1 / contact_stiffness, a unilateral constraint whose multiplier gives the
//     contact force (λ / h² per node);
//     and the bed, a rigid frictionless plane the vessel lies on (no node
//     below it), standing in for the tissue around a real vessel;
//  3. velocities from the corrected positions.
// The display surface (outer wall and lumen) follows the nodes through the
// MLS map (meshless/mls_surface_map.h), precomputed at rest.
//
// Force on the device: the sum of the contact forces on the tool, rendered by
// the bridge as a contact plane through the tip along that force, with the
// wall's tangent stiffness estimated from the last ticks' force and tip
// travel (capped by render_stiffness_max_N_per_m), not a constant.
//
// Baselines (parameter `model`), on the same nodes, contact and bed: a plain
// mass-spring wall (springs on the lattice's edges and diagonals with
// k = E x rest length, explicit like the meshless forces) and plain PBD
// (the same springs as distance constraints projected with the paper's
// stiffness scale k, no multipliers: its stiffness depends on sweeps and step).
//
// Departures, stated: the explicit forces need small steps for real wall
// masses, so node masses are scaled (mass_scale; statics unchanged) — see
// vessel_params.h; the paper's per-tetrahedron energy constraint is not in
// this scene yet.
#pragma once
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "hapsim/core/meshless/meshless_forces.h"
#include "hapsim/core/meshless/meshless_model.h"
#include "hapsim/core/meshless/mls_surface_map.h"
#include "hapsim/core/pbd/xpbd.h"
#include "hapsim/core/scenes/event_log.h"
#include "hapsim/core/scenes/scene.h"
#include "hapsim/core/scenes/scene_state_hash.h"
#include "hapsim/core/scenes/vessel/vessel_geometry.h"
#include "hapsim/core/scenes/vessel/vessel_params.h"
#include "hapsim/core/spatial/uniform_grid.h"

namespace hapsim::core {

class VesselScene final : public Scene {
 public:
  explicit VesselScene(const VesselParams& params);  // throws std::invalid_argument

  std::string_view Name() const override { return "vessel"; }
  void Step(const ToolInput& tool, double dt_s) override;
  void Reset() override;
  double SimTime_s() const override { return time_s_; }
  const Eigen::Matrix3Xd& Vertices_m() const override { return surface_m_; }
  const MeshTopology& Topology() const override { return topology_; }
  LocalForceModel ForceModel() const override { return force_model_; }
  Eigen::Vector3d ToolForce_W_N() const override { return tool_force_W_N_; }
  std::span<const SceneEvent> Events() const override { return events_.View(); }
  std::uint64_t EventsTotal() const override { return events_.TotalPushed(); }
  const SceneStatus& Status() const override { return status_; }
  std::uint64_t StateHash() const override;

  // For tests, validation and benchmarks.
  const VesselGeometry& Geometry() const { return geometry_; }
  const MeshlessModel& Model() const { return model_; }
  const Eigen::Matrix3Xd& Nodes_m() const { return x_m_; }
  const VesselParams& Params() const { return params_; }
  double StrainEnergy_J() const { return strain_energy_J_; }
  double MassScale() const { return mass_scale_; }  // the one in use (automatic when the parameter is 0)

 private:
  void BuildLattice(double spacing_m);
  bool Advance(const ToolInput& tool, bool tool_ok, double h_s);  // false: blew up
  void UpdateOutputs(const ToolInput& tool, bool tool_ok);
  void RecoverFromBlowup();

  VesselParams params_;
  VesselGeometry geometry_;
  MeshlessModel model_;
  MlsSurfaceMap surface_map_;
  VesselModel kind_ = VesselModel::kMeshlessXpbd;
  std::vector<DistanceConstraint> stretch_;  // meshless_xpbd: the paper's stretching constraints (lattice edges)
  // Baselines: springs on the lattice's edges and diagonals (compliance =
  // 1 / k with k = E x rest length), forces for mass_spring, plain-PBD
  // constraints for plain_pbd.
  std::vector<DistanceConstraint> springs_;
  std::vector<TetEnergyConstraint> tets_;  // meshless_xpbd with tet_fraction > 0
  Eigen::VectorXd tet_lambda_;
  UniformGrid rest_grid_;  // rest positions: contact candidates
  double bed_z_m_ = 0.0;      // the vessel lies on a rigid plane at its lowest rest point
  double mass_scale_ = 1.0;

  // State.
  Eigen::Matrix3Xd x_m_, v_m_per_s_;
  double time_s_ = 0.0;
  bool was_in_contact_ = false;
  int ticks_without_force_ = 0;
  double render_stiffness_N_per_m_ = 0.0;  // tangent estimate (EMA)
  Eigen::Vector3d last_tip_W_m_ = Eigen::Vector3d::Zero();
  double last_force_N_ = 0.0;

  // Scratch (sized at build; pure functions of the state within a step).
  Eigen::Matrix3Xd x_start_m_, elastic_N_, surface_m_;
  std::vector<Eigen::Matrix3d> F_;
  Eigen::VectorXd stretch_lambda_;
  std::vector<std::uint32_t> candidates_;
  std::vector<double> contact_lambda_;
  double strain_energy_J_ = 0.0;

  MeshTopology topology_;
  LocalForceModel force_model_;
  Eigen::Vector3d tool_force_W_N_ = Eigen::Vector3d::Zero();
  EventLog events_;
  SceneStatus status_;
  ResetEpoch reset_epoch_;
};

}  // namespace hapsim::core
