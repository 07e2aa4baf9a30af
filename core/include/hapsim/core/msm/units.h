// The one place where the papers' units (mm, N/mm, N·s/mm) become SI.
// Everything inside hapsim::core is SI (m, kg, s, N); convert at the edge
// with these and name the result with its unit.
#pragma once

namespace hapsim::core::units {

constexpr double MmToM(double mm) { return mm * 1e-3; }
constexpr double MToMm(double m) { return m * 1e3; }
// Spring stiffness: 1 N/mm = 1000 N/m (the papers' skin K = 0.16 N/mm = 160 N/m).
constexpr double NPerMmToNPerM(double n_per_mm) { return n_per_mm * 1e3; }
// Damping: 1 N·s/mm = 1000 N·s/m.
constexpr double NsPerMmToNsPerM(double ns_per_mm) { return ns_per_mm * 1e3; }
// Pressure/stress: 1 kPa = 1000 Pa (N/m²).
constexpr double KPaToPa(double kpa) { return kpa * 1e3; }

}  // namespace hapsim::core::units
