#include "hapsim/core/msm/integrator_kind.h"

#include <cmath>

namespace hapsim::core {

const char* ToString(IntegratorKind k) {
  switch (k) {
    case IntegratorKind::kExplicitEuler: return "explicit_euler";
    case IntegratorKind::kSymplecticEuler: return "symplectic_euler";
    case IntegratorKind::kImprovedEuler: return "improved_euler";
    case IntegratorKind::kMidpointAveraging: return "midpoint_averaging";
    case IntegratorKind::kRk4: return "rk4";
    case IntegratorKind::kBackwardEuler: return "backward_euler";
  }
  return "unknown";
}

std::optional<IntegratorKind> IntegratorFromString(std::string_view name) {
  for (int k = 0; k < kNumIntegratorKinds; ++k) {
    const auto kind = static_cast<IntegratorKind>(k);
    if (name == ToString(kind)) return kind;
  }
  return std::nullopt;
}

std::optional<IntegratorKind> IntegratorFromCode(double code) {
  if (!(code >= 0.0 && code < kNumIntegratorKinds) || std::floor(code) != code) return std::nullopt;
  return static_cast<IntegratorKind>(static_cast<int>(code));
}

}  // namespace hapsim::core
