// Perceptual deadband for the force models a session sends (Hinterseer et
// al.; Weber's law for force: a change under ~7 % of the force felt is not
// noticed). A model goes out when the device would feel the difference
// from the one it holds, else only as a keep-alive. "Feel the difference":
// both models evaluated where the tool is, and 1 mm further into the
// tissue along the new model's normal (so a stiffness change is seen at
// zero penetration too), differ by more than jnd x max(|force|, floor).
// A change of contact state always goes out. Runs on the tick; allocates
// nothing.
#pragma once
#include <cstdint>

#include "hapsim/core/haptics/local_force_model.h"
#include "hapsim/core/scenes/scene.h"

namespace hapsim::service {

struct ModelDeadbandConfig {
  double jnd = 0.0;              // Weber fraction of force (0: every model goes out)
  double floor_N = 0.02;         // below this force, changes are judged against it (detection threshold)
  double keepalive_s = 0.025;    // an unchanged model still goes out this often
  double probe_depth_m = 0.001;  // the second place models are compared, into the tissue
};

class ModelDeadband {
 public:
  explicit ModelDeadband(const ModelDeadbandConfig& config);

  // Would the device feel `model` differ from the last one sent, for the
  // tool where it is now (or is the keep-alive due)? Records it as sent if so.
  bool Offer(const core::LocalForceModel& model, const core::ToolInput& tool, std::int64_t now_ns);

  // After a send that was forced (or refused) elsewhere: next Offer compares with this.
  void Forget() { have_sent_ = false; }

 private:
  bool Differs(const core::LocalForceModel& model, const core::ToolInput& tool) const;

  ModelDeadbandConfig config_;
  std::int64_t keepalive_ns_;
  bool have_sent_ = false;
  core::LocalForceModel sent_;
  std::int64_t sent_ns_ = 0;
};

}  // namespace hapsim::service
