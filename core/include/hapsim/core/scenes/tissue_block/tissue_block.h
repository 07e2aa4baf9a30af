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
// Sleep: out of contact the block rings down to its rest state; once every
// node is within rest_displacement_m of it (and slow), the block is put
// exactly at rest and its steps are skipped until the tool touches it.
//
// Parameters: tissue_block_params.h (one table: names, units, ranges,
// defaults, descriptions; the cost limits of docs/scene-limits.md).
#pragma once
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "hapsim/core/msm/integrator_kind.h"
#include "hapsim/core/msm/local_region.h"
#include "hapsim/core/msm/msm_model.h"
#include "hapsim/core/msm/msm_state.h"
#include "hapsim/core/msm/msm_step.h"
#include "hapsim/core/msm/units.h"
#include "hapsim/core/scenes/scene.h"
#include "hapsim/core/scenes/scene_outputs.h"
#include "hapsim/core/scenes/tissue_block/tissue_block_params.h"

namespace hapsim::core {

// The scene's mass-spring grid as a plain definition (also used by the
// validation and the benchmarks to build larger patches of the same tissue).
MsmDef MakeTissueGridDef(const TissueBlockParams& params);

class TissueBlockScene final : public SceneWithOutputs {
 public:
  // Throws std::invalid_argument for bad parameters, including a dt_s above
  // the integrator's critical step (with the limit in the message).
  explicit TissueBlockScene(const TissueBlockParams& params);

  std::string_view Name() const override { return "tissue_block"; }
  void Step(const ToolInput& tool, double dt_s) override;
  void Reset() override;
  double SimTime_s() const override { return state_.t_s; }
  const Eigen::Matrix3Xd& Vertices_m() const override { return state_.x_m; }
  const MeshTopology& Topology() const override { return topology_; }
  std::uint64_t StateHash() const override;
  std::unique_ptr<const Scene> SaveState() const override { return std::make_unique<const TissueBlockScene>(*this); }
  void RestoreState(const Scene& saved) override { AssignSavedState(*this, saved); }

  // For tests and tools.
  const MsmModel& Model() const { return model_; }
  const MsmState& State() const { return state_; }
  const TissueBlockParams& Params() const { return params_; }
  double CriticalTimeStep_s() const { return critical_dt_s_; }
  // At rest out of contact: Step() only runs the clock and the contact test.
  bool Asleep() const { return asleep_; }
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
  void SleepIfAtRest();
  void PutAtRest();  // the initial state, keeping the clock and the blow-up count

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
  // Sleep (rest_displacement_m): while asleep the state is exactly the
  // initial state (with its own clock), so nothing but the contact test runs.
  bool asleep_ = false;
  double rest_speed_m_per_s_ = 0.0;  // rest_displacement_m x sqrt(anchor stiffness / node mass)

  MeshTopology topology_;  // the grid's nodes and triangles; never edited
};

}  // namespace hapsim::core
