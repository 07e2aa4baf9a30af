// One builder per scene family; MakeScene() dispatches to these by name.
// Each throws std::invalid_argument on an unknown or out-of-range parameter.
#pragma once
#include <map>
#include <memory>
#include <string>

#include "hapsim/core/scenes/scene.h"

namespace hapsim::core {

std::unique_ptr<Scene> MakeAcupunctureScene(const std::map<std::string, double>& params);
std::unique_ptr<Scene> MakeCuttingScene(const std::map<std::string, double>& params);
std::unique_ptr<Scene> MakeTissueBlockScene(const std::map<std::string, double>& params);
std::unique_ptr<Scene> MakeVesselScene(const std::map<std::string, double>& params);

}  // namespace hapsim::core
