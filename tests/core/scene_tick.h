// The step the scene tests take: one server tick [s].
#pragma once

namespace hapsim::core {

inline constexpr double kTick_s = 1e-3;

}  // namespace hapsim::core
