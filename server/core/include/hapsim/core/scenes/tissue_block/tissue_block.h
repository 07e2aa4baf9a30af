// tissue_block: a square patch of soft tissue pressed by a needle.
//
// Model: a surface grid of nodes at z = 0 (edges fixed) joined by structural
// (grid edges) and shear (cell diagonals) springs, every node also tied by a
// zero-length anchor spring to its rest position — the "anchored springs"
// substrate that stands in for the tissue underneath. The surface springs
// are pre-stretched (rest length < grid spacing) like skin in vivo, which
// gives the membrane transverse stiffness, so a press spreads into a dimple.
//
// Contact: the needle tip is a point; the surface height under it is the
// bilinear interpolation of the four corner nodes of the grid cell that
// contains the tip (cell found from the tip's x, y in the rest grid, so the
// tip can never slip between nodes). Penetration p > 0 gives a penalty force
// F = max(0, k_c p + b_c dp/dt) on the tool along +z and -w_a F on the
// corner nodes (bilinear weights w_a): equal and opposite, real deformation.
//
// Parameters (SceneSpec::params, SI, defaults in TissueBlockParams):
//   grid_nodes, size_m, spring_stiffness_N_per_m, shear_stiffness_N_per_m,
//   spring_damping_Ns_per_m, anchor_stiffness_N_per_m, damping_Ns_per_m,
//   node_mass_kg, prestretch, contact_stiffness_N_per_m,
//   contact_damping_Ns_per_m, max_penetration_m,
//   dt_s, integrator (IntegratorKind code: 0 explicit Euler, 1 symplectic
//   Euler, 2 improved Euler, 3 midpoint-averaging, 4 RK4, 5 backward Euler),
//   midpoint_alpha, local_update_hops (0 = integrate every node; N > 0 =
//   while in contact, integrate only nodes within N spring hops of the
//   contact, the gingival paper's local update), max_kinetic_energy_J.
//
// Cost limits (docs/scene-limits.md): grid_nodes <= 101, dt_s >= 1e-6 s and
// TissueBlockStepCost() <= kMaxStepCost, so a client cannot ask for a tick
// that takes more than ~0.3 ms of CPU. Backward Euler runs at most
// kMaxCgIterations conjugate-gradient iterations per sub-step (the default
// tissue converges in ~10); a stiffer system gets the truncated solve.
#pragma once
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "hapsim/core/msm/integrator_kind.h"
#include "hapsim/core/msm/msm_step.h"
#include "hapsim/core/msm/local_region.h"
#include "hapsim/core/msm/msm_model.h"
#include "hapsim/core/msm/msm_state.h"
#include "hapsim/core/msm/units.h"
#include "hapsim/core/scenes/event_log.h"
#include "hapsim/core/scenes/scene.h"
#include "hapsim/core/scenes/scene_state_hash.h"

namespace hapsim::core {

struct TissueBlockParams {
  int grid_nodes = 21;                      // nodes per side, [3, 101]
  double size_m = 0.06;                     // side length of the patch [m]
  // Skin spring stiffness of the acupuncture/cutting papers, K = 0.16 N/mm.
  double spring_stiffness_N_per_m = units::NPerMmToNPerM(0.16);
  double shear_stiffness_N_per_m = units::NPerMmToNPerM(0.16);
  double spring_damping_Ns_per_m = 0.02;    // along each surface spring
  // Per-node anchor: with the defaults a 5 mm press gives about 1 N.
  double anchor_stiffness_N_per_m = 40.0;
  double damping_Ns_per_m = 0.5;            // per node, absolute (substrate drag)
  double node_mass_kg = 2.5e-3;              // lumped; sets the explicit critical step
  double prestretch = 0.05;                 // rest length = spacing / (1 + prestretch)
  double contact_stiffness_N_per_m = 1000.0;  // needle-surface penalty
  // Penalty damper on the penetration rate: without it the light surface
  // nodes bounce off the tip and contact chatters on first touch.
  double contact_damping_Ns_per_m = 0.8;
  double max_penetration_m = 0.02;          // deeper tips are treated as this deep
  double dt_s = 1e-3;                       // largest internal step; Step() sub-steps to it
  IntegratorChoice integrator{};            // default symplectic Euler
  int local_update_hops = 0;                // 0 = full update every step
  // Stability guard: a step above this kinetic energy counts as a blow-up
  // and resets the scene. The patch never gets near 10 J under a hand.
  double max_kinetic_energy_J = 10.0;
};

// What a client may ask for, so that a build takes milliseconds and one 1 ms
// Step() at most ~0.3 ms of CPU (measured: docs/scene-limits.md).
struct TissueBlockLimits {
  static constexpr int kMaxGridNodes = 101;
  // 1000 sub-steps per 1 ms tick; Step() never runs more (kMaxSubsteps).
  static constexpr double kMinDt_s = 1e-6;
  static constexpr int kMaxCgIterations = 20;  // backward Euler, per sub-step
  // Budget for TissueBlockStepCost(): 1 unit ~ 13 ns here; the worst
  // accepted combinations measured p50 <= 0.17 ms, p99 <= 0.19 ms.
  static constexpr double kMaxStepCost = 12000.0;
};

// Estimated CPU cost of one 1 ms Step() in node updates (one node through
// one symplectic Euler sub-step):
//   grid_nodes^2 x ceil(1 ms / dt_s) x integrator factor
//   (explicit 1.5, symplectic 1, improved 1.5, midpoint 2.5, RK4 5,
//    backward Euler 4 + 1.1 per CG iteration = 26),
// with local_update_hops > 0 times 1.15 (indexed node lists; a step out of
// contact still updates every node) plus 8 per node of the region
// re-selected when the contact moves (at most once per Step()).
double TissueBlockStepCost(const TissueBlockParams& params);

// The scene's mass-spring grid as a plain definition (also used by the
// validation and the benchmarks to build larger patches of the same tissue).
MsmDef MakeTissueGridDef(const TissueBlockParams& params);

// Parses and range-checks params, including TissueBlockLimits; unknown keys
// and bad values throw std::invalid_argument naming the key(s) and the
// allowed range.
TissueBlockParams ParseTissueBlockParams(const std::map<std::string, double>& params);

class TissueBlockScene final : public Scene {
 public:
  // Throws std::invalid_argument for bad parameters, including a dt_s above
  // the integrator's critical step (with the limit in the message).
  explicit TissueBlockScene(const TissueBlockParams& params);

  std::string_view Name() const override { return "tissue_block"; }
  void Step(const ToolInput& tool, double dt_s) override;
  void Reset() override;
  double SimTime_s() const override { return state_.t_s; }
  const Eigen::Matrix3Xd& Vertices_m() const override { return state_.x_m; }
  const std::vector<std::uint32_t>& Triangles() const override { return triangles_; }
  const std::vector<SurfacePart>& Parts() const override { return parts_; }
  std::uint64_t TopologyVersion() const override { return 1; }
  LocalForceModel ForceModel() const override { return force_model_; }
  Eigen::Vector3d ToolForce_W_N() const override { return tool_force_W_N_; }
  std::span<const SceneEvent> Events() const override { return events_.View(); }
  std::uint64_t EventsTotal() const override { return events_.TotalPushed(); }
  const SceneStatus& Status() const override { return status_; }
  std::uint64_t StateHash() const override;

  // For tests and tools.
  const MsmModel& Model() const { return model_; }
  const MsmState& State() const { return state_; }
  const TissueBlockParams& Params() const { return params_; }
  double CriticalTimeStep_s() const { return critical_dt_s_; }
  std::int32_t NodeIndex(int row, int col) const { return row * params_.grid_nodes + col; }

 private:
  // Contact of the tip with the bilinear surface at the current state.
  struct Contact {
    bool active = false;
    double penetration_m = 0.0;       // clamped to max_penetration_m
    double push_N = 0.0;              // force on the tool along +z (>= 0)
    std::array<std::int32_t, 4> nodes{};
    std::array<double, 4> weights{};
  };
  Contact FindContact(const ToolInput& tool) const;
  void ApplyContactForce(const Contact& c);
  void UpdateOutputs(const ToolInput& tool, const Contact& c);
  double LocalSurfaceStiffness_N_per_m(const Contact& c) const;
  void RecoverFromBlowup();
  StepReport Advance(const Contact& c, double h_s);

  TissueBlockParams params_;
  MsmModel model_;
  MsmState state_;
  MsmState initial_state_;
  MsmWorkspace workspace_;
  LocalRegion region_;
  // Node the region is centred on: a cache (the region is a pure function of
  // it), kept across contact breaks so a chattering contact does not
  // re-select the region every sub-step.
  std::int32_t region_seed_ = -1;
  double critical_dt_s_ = 0.0;
  double spacing_m_ = 0.0;
  std::array<std::int32_t, 4> loaded_nodes_{};  // nodes carrying contact f_ext
  bool was_in_contact_ = false;

  std::vector<std::uint32_t> triangles_;
  std::vector<SurfacePart> parts_;
  LocalForceModel force_model_;
  Eigen::Vector3d tool_force_W_N_ = Eigen::Vector3d::Zero();
  EventLog events_;
  SceneStatus status_;
  ResetEpoch reset_epoch_;
};

}  // namespace hapsim::core
