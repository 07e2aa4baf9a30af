// vessel: a blood vessel's wall pressed by a catheter / probe tip (vascular
// paper, Zhang et al. 2021).
//
// Model, per physics step of h = tick / substeps — one StepXpbd (pbd/xpbd.h,
// the step the XPBD tests prove):
//  1. meshless elastic forces on the wall's nodes (meshless/, Müller et al.
//     2004) and the lumen's blood pressure on the inner wall as the step's
//     external forces: StepXpbd's explicit prediction with damping;
//  2. XPBD constraint sweeps: the paper's stretching constraints between
//     lattice neighbours (axial, around, across the wall) with compliance
//     1 / (stretch_fraction E spacing), then, per sweep, this scene's own
//     (VesselConstraints): the paper's per-tetrahedron energy constraints
//     (tet_fraction), the foundation's tethers (the tissue around the
//     vessel, tissue_modulus_Pa), the tip's contact — each node inside the
//     probe sphere is pushed out with compliance 1 / contact_stiffness, a
//     unilateral constraint whose multiplier gives the contact force
//     (λ / h² per node) — and the bed, a rigid frictionless plane under the
//     vessel (no node below it);
//  3. velocities from the corrected positions.
// The tip the physics sees moves at most kMaxTipTravelPerStep_m per step
// toward the device's: a late tick's jump is spread over the next steps
// instead of hitting the scaled masses at once; it never goes below where
// the vessel's two flattened walls would lie on the bed.
// The display surface (outer wall and lumen) follows the nodes through the
// MLS map (meshless/mls_surface_map.h), precomputed at rest, mapped when
// Vertices_m() is asked.
//
// The wall sleeps (VesselParams::rest_speed_m_per_s): once every node has
// moved slower than the rest speed for kQuietStepsToSleep steps while the
// tip stood still or touched nothing, steps are skipped and the wall kept
// as it stands (velocities zero) until the probe sphere reaches a node or,
// asleep under the probe, the tip moves or the tool is lost. It neglects
// at most rest speed / damping of creep (docs/validation.md#vessel).
//
// Force on the device: the sum of the contact forces on the tool, plus the
// skin over the vessel (VesselParams::skin: a half-space of the tissue the
// probe indents, in parallel, skin_indentation.h), rendered by
// the bridge as a contact plane through the tip along that force, with the
// stiffness of the wall's settled force-depth curve at the tip's depth
// (vessel_settled_curve.h: the same scene pressed quasi-statically at build).
//
// Baselines (parameter `model`), on the same nodes, contact and bed: a plain
// mass-spring wall (springs on the lattice's edges and diagonals with
// k = E x rest length, explicit like the meshless forces) and plain PBD
// (the same springs as distance constraints projected with the paper's
// stiffness scale k, no multipliers: its stiffness depends on sweeps and step).
//
// Departures, stated: the explicit forces need small steps for real wall
// masses, so node masses are scaled (mass_scale; statics unchanged) — see
// vessel_params.h.
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
#include "hapsim/core/scenes/scene.h"
#include "hapsim/core/scenes/scene_outputs.h"
#include "hapsim/core/scenes/vessel/vessel_geometry.h"
#include "hapsim/core/scenes/vessel/vessel_params.h"
#include "hapsim/core/scenes/vessel/vessel_settled_curve.h"
#include "hapsim/core/spatial/uniform_grid.h"

namespace hapsim::core {

class VesselScene final : public SceneWithOutputs {
 public:
  explicit VesselScene(const VesselParams& params);  // throws std::invalid_argument

  std::string_view Name() const override { return "vessel"; }
  void Step(const ToolInput& tool, double dt_s) override;
  void Reset() override;
  double SimTime_s() const override { return time_s_; }
  const Eigen::Matrix3Xd& Vertices_m() const override;  // the MLS map of the nodes, mapped when asked
  const MeshTopology& Topology() const override { return topology_; }
  std::uint64_t StateHash() const override;
  std::unique_ptr<const Scene> SaveState() const override { return std::make_unique<const VesselScene>(*this); }
  void RestoreState(const Scene& saved) override { AssignSavedState(*this, saved); }

  // For tests, validation and benchmarks.
  const VesselGeometry& Geometry() const { return geometry_; }
  const MeshlessModel& Model() const { return model_; }
  const Eigen::Matrix3Xd& Nodes_m() const { return wall_.x_m; }
  const VesselParams& Params() const { return params_; }
  double StrainEnergy_J() const { return strain_energy_J_; }
  double MassScale() const { return mass_scale_; }  // the one in use (automatic when the parameter is 0)
  // The wall pressed at build: what the device's stiffness is taken from.
  const VesselSettledCurve& SettledCurve() const { return settled_curve_; }
  // The skin's push on the probe at this tip [N, along +z] (0 with no skin).
  double SkinForce_N(const Eigen::Vector3d& tip_W_m) const;
  // Where the physics' tip is (it follows the device's at a bounded travel per step).
  const Eigen::Vector3d& PhysicsTip_W_m() const { return tip_W_m_; }
  // The probe's depth into the undeformed wall [m]: how far the tip sphere
  // reaches past the rest outer surface of the nearest station (< 0: clear).
  double DepthIntoRestWall_m(const Eigen::Vector3d& tip_W_m) const;

  // Whether the wall sleeps (VesselParams::rest_speed_m_per_s): its step is
  // skipped and its state kept until the tip wakes it.
  bool Asleep() const { return asleep_; }

  // Largest travel of the physics' tip in one physics step [m] (20 mm/s at 1 kHz).
  static constexpr double kMaxTipTravelPerStep_m = 2e-5;
  // Quiet steps in a row before the wall sleeps.
  static constexpr int kQuietStepsToSleep = 20;

 private:
  // The constraints this scene projects in each XPBD sweep after the
  // stretching constraints: tetrahedra, the foundation, the tip, the bed.
  class VesselConstraints final : public XpbdExtraConstraints {
   public:
    explicit VesselConstraints(VesselScene& scene) : scene_(scene) {}
    void BeginStep() override;
    void Project(Eigen::Matrix3Xd& x_m, const Eigen::VectorXd& inv_mass_per_kg, double h_s) override;

   private:
    VesselScene& scene_;
  };

  // The constructor's steps, in order.
  void BuildMeshlessWall(double support_radius_m);
  void BuildLattice(double spacing_m, std::vector<DistanceConstraint>& stretch);
  void BuildLatticeTets(double spacing_m);  // BuildLattice's first step: tets_
  void BuildFoundation(const VesselGeometryDef& def);
  void ScaleMassesForStability();  // throws std::invalid_argument if even the scaled step is unstable
  void BuildWallStep(std::vector<DistanceConstraint> stretch);
  void SizeStepScratch(double spacing_m);
  void BuildDisplay(double support_radius_m);
  void OrientLumenPressure();
  void MeasureSettledCurve();              // at build: settled_curve_
  void Inflate();                          // at build: the wall settled under the lumen pressure, inflated_m_
  void AddLumenPressure();                 // the pressure's nodal forces on the inner wall, into wall_.f_ext_N
  bool Advance(bool tool_ok, double h_s);  // false: blew up
  // Advance's steps, in order (StepXpbd between the forces and the tool's force).
  // candidates_: nodes that may be inside the probe, given the largest
  // displacement of any node from rest.
  void FindContactCandidates(bool tool_ok, double max_displacement_m);
  void ComputeElasticForces();               // into wall_.f_ext_N, strain_energy_J_
  void SumToolContactForce(double h_s);      // outputs_.tool_force_W_N
  struct WallMotion {
    double kinetic_J = 0.0;
    double max_speed_m_per_s = 0.0;
  };
  WallMotion MeasureWallMotion() const;
  // Sleeping (rest_speed_m_per_s > 0): after a step, counts it quiet or
  // not and lets the wall sleep; before a step, whether the sleeping wall
  // stays asleep (the tip neither reaches a node nor leaves its contact).
  void CountQuietStep(const WallMotion& motion);
  void FallAsleep();
  bool StaysAsleep(bool tool_ok);
  bool AsleepInContact() const { return !sleep_contact_force_W_N_.isZero(0.0); }
  void UpdateOutputs(const ToolInput& tool, bool tool_ok);
  void RecoverFromBlowup();

  VesselParams params_;
  VesselGeometry geometry_;
  double outer_radius_m_ = 0.0;
  // The skin's surface: the level plane through the vessel's top at rest
  // (VesselParams::skin; used only when skin_on_).
  double skin_top_z_m_ = 0.0;
  bool skin_on_ = false;
  MeshlessModel model_;
  MlsSurfaceMap surface_map_;
  VesselModel kind_ = VesselModel::kMeshlessXpbd;
  XpbdModel wall_model_;  // the wall's nodes (scaled masses) and its distance constraints
  // Baselines: springs on the lattice's edges and diagonals (compliance =
  // 1 / k with k = E x rest length), forces for mass_spring (plain_pbd's are
  // in wall_model_).
  std::vector<DistanceConstraint> springs_;
  std::vector<TetEnergyConstraint> tets_;  // meshless_xpbd with tet_fraction > 0
  // The foundation: node i held at its rest position with compliance [m/N].
  std::vector<std::int32_t> tether_node_;
  std::vector<double> tether_compliance_m_per_N_;
  UniformGrid rest_grid_;  // rest positions: contact candidates
  double bed_z_m_ = 0.0;      // the vessel lies on a rigid plane at its lowest rest point
  double probe_floor_z_m_ = 0.0;  // the physics tip stays above: the bed + the probe + the flattened walls
  double mass_scale_ = 1.0;
  double lumen_outward_sign_ = 1.0;  // orients the inner wall's tangent cross product out of the lumen
  VesselSettledCurve settled_curve_;
  Eigen::Matrix3Xd inflated_m_;  // the wall at rest under the lumen pressure (Reset's state)

  // State.
  XpbdState wall_;  // positions, velocities (f_ext_N: the step's elastic forces)
  Eigen::Vector3d tip_W_m_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d tip_at_step_start_W_m_ = Eigen::Vector3d::Zero();  // per-step scratch: the friction's reference
  bool tip_placed_ = false;  // false until the first valid pose (then tip_W_m_ follows it)
  double time_s_ = 0.0;
  bool was_in_contact_ = false;
  int ticks_without_force_ = 0;
  // Sleep: off while the build inflates and presses the wall (its curve
  // and rest state are the full step's). While asleep the wall's x and v
  // (zero) are kept, and so is the contact force it gave when it fell asleep.
  bool sleep_allowed_ = false;
  bool asleep_ = false;
  int quiet_steps_ = 0;
  Eigen::Vector3d sleep_tip_W_m_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d sleep_contact_force_W_N_ = Eigen::Vector3d::Zero();
  double sleep_max_displacement_m_ = 0.0;

  // Scratch (sized at build; pure functions of the state within a step).
  std::vector<Eigen::Matrix3d> F_;
  Eigen::VectorXd tet_lambda_, tether_lambda_;
  std::vector<std::uint32_t> candidates_;
  std::vector<double> contact_lambda_;
  double strain_energy_J_ = 0.0;
  // The display surface, mapped from the nodes when Vertices_m() is asked
  // after a step moved them (~9 % of a tick: viewers take it at frame rate).
  mutable Eigen::Matrix3Xd surface_m_;
  mutable bool surface_stale_ = false;

  MeshTopology topology_;
};

}  // namespace hapsim::core
