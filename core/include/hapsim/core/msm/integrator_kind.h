// The time integrators a scene can choose. Definitions (a = f/m everywhere;
// the gingival paper's eq. (4) drops the /m in one line — a typo):
//   kExplicitEuler:      x' = x + h v;            v' = v + h a(x,v)
//   kSymplecticEuler:    v' = v + h a(x,v);       x' = x + h v'
//   kImprovedEuler:      v' = v + h a(x,v);       x' = x + h/2 (v + v')
//   kMidpointAveraging:  v* = v + alpha h a(x,v); x* = x + alpha h v*;
//                        v' = v + h a(x*,v*);     x' = x + h/2 (v + v')
//   kRk4:                classic 4-stage Runge-Kutta on (x, v)
//   kBackwardEuler:      (M - h C - h^2 K) dv = h (f + h K v); v' = v + dv;
//                        x' = x + h v'  (Baraff-Witkin 1998: one linearised
//                        Newton step, solved by conjugate gradients)
#pragma once
#include <cstdint>
#include <optional>
#include <string_view>

namespace hapsim::core {

enum class IntegratorKind : std::uint8_t {
  kExplicitEuler = 0,
  kSymplecticEuler = 1,
  kImprovedEuler = 2,
  kMidpointAveraging = 3,
  kRk4 = 4,
  kBackwardEuler = 5,
};
constexpr int kNumIntegratorKinds = 6;

const char* ToString(IntegratorKind k);
std::optional<IntegratorKind> IntegratorFromString(std::string_view name);
// Numeric code (the enum value) as used in scene parameter maps.
std::optional<IntegratorKind> IntegratorFromCode(double code);

struct IntegratorChoice {
  IntegratorKind kind = IntegratorKind::kSymplecticEuler;
  double alpha = 0.5;  // midpoint-averaging weight (kMidpointAveraging only), in (0, 1]
};

}  // namespace hapsim::core
