// Scene: one simulated tissue set-up a session runs (tissue block, acupuncture,
// ...). The service drives it once per tick: Step(tool, dt) with the latest
// tool pose, then reads the mesh, the force model for the device and events.
//
// Contract:
//  - built by MakeScene() from a SceneSpec; bad parameters throw
//    std::invalid_argument with a message naming the parameter;
//  - after construction Step() never throws and never allocates;
//  - numerical blow-up inside Step() is detected, counted in
//    Status().numerical_resets, and the scene resets itself — never a crash;
//  - same inputs, same outputs (deterministic; no clocks, no randomness
//    without a fixed seed).
// World frame W: tissue top surface near z = 0 with outward normal +z, tissue
// below (z < 0). Units SI.
#pragma once
#include <cstdint>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "hapsim/core/haptics/local_force_model.h"
#include "hapsim/core/mesh/mesh_topology.h"
#include "hapsim/core/scenes/param_table.h"

namespace hapsim::core {

// The tool as the device reports it for one tick.
struct ToolInput {
  bool valid = false;  // false until the first pose arrives: the tool is absent
  Eigen::Vector3d tip_W_m = Eigen::Vector3d(0, 0, 0.05);  // needle/blade tip [m]
  // Tool orientation. Insertion direction (tip forward) = orientation * (0,0,-1),
  // so the identity points the needle straight down into the tissue.
  Eigen::Quaterniond orientation_W = Eigen::Quaterniond::Identity();
  Eigen::Vector3d velocity_W_m_per_s = Eigen::Vector3d::Zero();
  std::uint32_t buttons = 0;
};

// A reported tool speed past this is no hand's [m/s]: the scenes that use the
// tool's velocity (contact damping, the blade's sweep) clamp it here.
inline constexpr double kMaxToolSpeed_m_per_s = 10.0;

enum class SceneEventKind : std::uint8_t {
  kContactBegin = 0,
  kContactEnd = 1,
  kPuncture = 2,
  kCutStart = 3,  // a blade began an incision (where: its start)
  kReset = 4,
  kCutEnd = 5,    // the blade left the incision (where: its end; value: its length [m])
};
const char* ToString(SceneEventKind k);

struct SceneEvent {
  double t_s = 0.0;  // sim time of the event
  SceneEventKind kind = SceneEventKind::kContactBegin;
  int layer = -1;    // index into Status().layer_names, -1 if none
  Eigen::Vector3d where_W_m = Eigen::Vector3d::Zero();
  double value = 0.0;  // kCutEnd: incision length [m]; 0 otherwise
};

struct SceneStatus {
  std::vector<std::string> layer_names;  // fixed at build
  int current_layer = -1;                // layer the tip is in or touching, -1 none
  double tip_depth_m = 0.0;              // depth of the tip below the top surface (>= 0)
  std::uint64_t numerical_resets = 0;    // blow-ups detected and recovered
};

class Scene {
 public:
  virtual ~Scene() = default;
  virtual std::string_view Name() const = 0;

  // Advances the simulation by dt_s with the tool held as given.
  virtual void Step(const ToolInput& tool, double dt_s) = 0;
  // Back to the initial state (topology version bumps if topology changed).
  virtual void Reset() = 0;

  virtual double SimTime_s() const = 0;
  // Displayed mesh: one column per vertex slot [m] (3 x vertex capacity;
  // the column count never changes after construction, and only the slots
  // live in Topology() mean anything), and its connectivity in stable slots
  // with parts and the log of every edit (cuts, punctures that remesh,
  // resets), from which viewers are updated incrementally. A scene may bring
  // its display up to date only when asked (viewers want it at frame rate,
  // not every tick): call it from the thread that steps the scene.
  virtual const Eigen::Matrix3Xd& Vertices_m() const = 0;
  virtual const MeshTopology& Topology() const = 0;

  // What the device should render until the next tick, and the force the
  // tissue exerts on the tool at this tick [N] (for plots and the bridge's
  // round-trip check).
  virtual LocalForceModel ForceModel() const = 0;
  virtual Eigen::Vector3d ToolForce_W_N() const = 0;

  // The most recent events, oldest first; bounded (the oldest are dropped
  // past the capacity reserved at build), so Step() never allocates. Reset()
  // does not clear them: it logs a kReset event instead.
  virtual std::span<const SceneEvent> Events() const = 0;
  // How many events were ever logged (monotonic; EventLog::TotalPushed()), so
  // a consumer can tell which of Events() it has not seen yet.
  virtual std::uint64_t EventsTotal() const = 0;
  virtual const SceneStatus& Status() const = 0;

  // Deterministic 64-bit hash (FNV-1a, state_hash.h) of every piece of
  // mutable state that influences future steps or what the scene shows:
  // node positions and velocities, forces held on nodes, sim time, contact /
  // puncture / layer state, needle state, the outputs of the last step
  // (force, force model, status) and the event and numerical-reset counts.
  // Same sequence of Step()/Reset() calls from a fresh scene => same hash
  // (on every run, thread count and spring kernel); any divergence of that
  // state changes it. Scratch buffers and caches that are a pure function of
  // hashed state are left out.
  //
  // Counters that Reset() deliberately keeps (EventsTotal(),
  // Status().numerical_resets) enter as their increase since the last
  // Reset() (the kReset event itself not counted), so right after Reset()
  // the hash equals a fresh scene's: nothing before a Reset() influences
  // anything after it but those running totals.
  //
  // Never allocates; O(state size) — tens of µs for the default scenes, so
  // call it at checkpoints (tests, recordings), not necessarily every tick.
  virtual std::uint64_t StateHash() const = 0;

  // The whole state as it is now, kept aside (for seeking in a replay): a
  // copy sized to its contents, so it cannot be stepped (it is const; the
  // headroom Step() relies on is not in it). RestoreState() puts it back
  // into a scene built from the same SceneSpec, which then goes on exactly
  // as this one would: the same StateHash() after every step, and Step()
  // still allocating nothing. Both allocate: never on a tick.
  virtual std::unique_ptr<const Scene> SaveState() const = 0;
  // Throws std::invalid_argument for a state saved from another kind of scene.
  virtual void RestoreState(const Scene& saved) = 0;
};

// Which scene to build and its parameters (SI, names with units, e.g.
// "grid_nodes", "stiffness_N_per_m"); unknown keys are an error.
struct SceneSpec {
  std::string name = "tissue_block";
  std::map<std::string, double> params;
};

// A scene MakeScene() accepts: its name, a one-line description and every
// parameter it takes (from the scene's parameter table), sorted by name.
struct SceneDescription {
  std::string name;
  std::string description;
  std::vector<ParamInfo> params;
};
std::vector<SceneDescription> SceneCatalog();

// Throws std::invalid_argument for an unknown scene or a bad parameter.
std::unique_ptr<Scene> MakeScene(const SceneSpec& spec);

}  // namespace hapsim::core
