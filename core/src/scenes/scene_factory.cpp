// The scene catalogue: name -> builder. Each scene family adds one entry.
#include <functional>
#include <stdexcept>

#include "hapsim/core/math/eigen_blocking.h"
#include "hapsim/core/scenes/acupuncture/acupuncture_params.h"
#include "hapsim/core/scenes/cutting/cutting_params.h"
#include "hapsim/core/scenes/scene.h"
#include "hapsim/core/scenes/scene_builders.h"
#include "hapsim/core/scenes/tissue_block/tissue_block_params.h"
#include "hapsim/core/scenes/vessel/vessel_params.h"

namespace hapsim::core {

const char* ToString(SceneEventKind k) {
  switch (k) {
    case SceneEventKind::kContactBegin: return "contact_begin";
    case SceneEventKind::kContactEnd: return "contact_end";
    case SceneEventKind::kPuncture: return "puncture";
    case SceneEventKind::kCutStart: return "cut_start";
    case SceneEventKind::kCutEnd: return "cut_end";
    case SceneEventKind::kReset: return "reset";
  }
  return "unknown";
}

namespace {

struct CatalogEntry {
  const char* name;
  const char* description;
  std::unique_ptr<Scene> (*build)(const std::map<std::string, double>& params);
  std::vector<ParamInfo> (*params)();
};

// Keep sorted by name.
constexpr CatalogEntry kCatalog[] = {
    {"acupuncture",
     "three-layer SH tissue (skin/fat/muscle), mass-spring force net, layered puncture and springback",
     &MakeAcupunctureScene, [] { return AcupunctureParamTable().Describe(); }},
    {"cutting",
     "scalpel incision on a skin patch: cylinder collision, three-stage progressive cut, residual-stress wound gape",
     &MakeCuttingScene, [] { return CuttingParamTable().Describe(); }},
    {"tissue_block",
     "soft tissue block: mass-spring surface grid over anchored springs, pressed by a needle",
     &MakeTissueBlockScene, [] { return TissueBlockParamTable().Describe(); }},
    {"vessel",
     "blood vessel wall (meshless point primitives + XPBD constraints, MLS surface) pressed by a probe tip",
     &MakeVesselScene, [] { return VesselParamTable().Describe(); }},
};

}  // namespace

std::vector<SceneDescription> SceneCatalog() {
  std::vector<SceneDescription> out;
  for (const auto& e : kCatalog) out.push_back({e.name, e.description, e.params()});
  return out;
}

std::unique_ptr<Scene> MakeScene(const SceneSpec& spec) {
  for (const auto& e : kCatalog) {
    if (spec.name == e.name) {
      PinEigenBlockingSizes();  // every scene builds the same state on every CPU
      return e.build(spec.params);
    }
  }
  std::string known;
  for (const auto& e : kCatalog) known += std::string(known.empty() ? "" : ", ") + e.name;
  throw std::invalid_argument("unknown scene '" + spec.name.substr(0, 80) + "' (known: " + known + ")");  // echo bounded
}

}  // namespace hapsim::core
