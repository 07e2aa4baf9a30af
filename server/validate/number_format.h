// Number formatting shared by the validation reports (markdown tables).
#pragma once
#include <cstdio>
#include <string>

namespace hapsim::validate {

// Scientific with `digits` decimals, e.g. Sci(0.000123) == "1.230e-04".
inline std::string Sci(double v, int digits = 3) {
  char b[64];
  std::snprintf(b, sizeof b, "%.*e", digits, v);
  return b;
}

// Fixed with `decimals` decimals, e.g. Fixed(1.5, 2) == "1.50".
inline std::string Fixed(double v, int decimals) {
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", decimals, v);
  return b;
}

}  // namespace hapsim::validate
