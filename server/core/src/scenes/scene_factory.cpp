// The scene catalogue: name -> builder. Each scene family adds one entry.
#include <functional>
#include <stdexcept>

#include "hapsim/core/scenes/scene.h"
#include "hapsim/core/scenes/scene_builders.h"

namespace hapsim::core {

const char* ToString(SceneEventKind k) {
  switch (k) {
    case SceneEventKind::kContactBegin: return "contact_begin";
    case SceneEventKind::kContactEnd: return "contact_end";
    case SceneEventKind::kPuncture: return "puncture";
    case SceneEventKind::kCut: return "cut";
    case SceneEventKind::kReset: return "reset";
  }
  return "unknown";
}

namespace {

struct CatalogEntry {
  const char* name;
  const char* description;
  std::unique_ptr<Scene> (*build)(const std::map<std::string, double>& params);
};

// Keep sorted by name.
constexpr CatalogEntry kCatalog[] = {
    {"acupuncture",
     "three-layer SH tissue (skin/fat/muscle), mass-spring force net, layered puncture and springback",
     &MakeAcupunctureScene},
    {"tissue_block",
     "soft tissue block: mass-spring surface grid over anchored springs, pressed by a needle",
     &MakeTissueBlockScene},
};

}  // namespace

std::vector<std::pair<std::string, std::string>> SceneCatalog() {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& e : kCatalog) out.emplace_back(e.name, e.description);
  return out;
}

std::unique_ptr<Scene> MakeScene(const SceneSpec& spec) {
  for (const auto& e : kCatalog) {
    if (spec.name == e.name) return e.build(spec.params);
  }
  std::string known;
  for (const auto& e : kCatalog) known += std::string(known.empty() ? "" : ", ") + e.name;
  throw std::invalid_argument("unknown scene '" + spec.name + "' (known: " + known + ")");
}

}  // namespace hapsim::core
