#include "hapsim/core/scenes/param_table.h"

#include <sstream>

namespace hapsim::core {

namespace {
std::string Number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}
}  // namespace

std::string DescribeRange(const ParamSpec& spec) {
  std::string out;
  if (spec.integer && !spec.choices.empty()) {
    out = "an integer code " + Number(spec.min) + ".." + Number(spec.max) + " (";
    for (std::size_t i = 0; i < spec.choices.size(); ++i) {
      out += (i ? ", " : "") + Number(spec.min + static_cast<double>(i)) + " " + spec.choices[i];
    }
    return out + ")";
  }
  if (spec.integer) out = "an integer ";
  const bool lo = std::isfinite(spec.min), hi = std::isfinite(spec.max);
  if (lo && hi) {
    out += "in " + std::string(spec.min_open ? "(" : "[") + Number(spec.min) + ", " + Number(spec.max) +
           (spec.max_open ? ")" : "]");
  } else if (lo) {
    out += (spec.min_open ? "> " : ">= ") + Number(spec.min);
  } else if (hi) {
    out += (spec.max_open ? "< " : "<= ") + Number(spec.max);
  } else {
    out += "finite";
  }
  return out;
}

std::string FormatParams(const std::vector<ParamInfo>& params, const std::string& indent) {
  std::ostringstream out;
  for (const auto& p : params) {
    std::ostringstream line;
    line << indent << p.spec.name;
    const std::string head = line.str();
    // Counts, codes and ratios carry no unit worth printing.
    const bool plain = p.spec.unit == "1" || p.spec.unit == "count" || p.spec.unit == "code";
    out << head << std::string(head.size() < 34 ? 34 - head.size() : 1, ' ') << "default " << Number(p.default_value)
        << (plain ? "" : " " + p.spec.unit) << ", " << DescribeRange(p.spec) << ": " << p.spec.description << "\n";
  }
  return out.str();
}

std::string CheckParamValue(const ParamSpec& spec, double value) {
  const bool ok = std::isfinite(value) && (spec.min_open ? value > spec.min : value >= spec.min) &&
                  (spec.max_open ? value < spec.max : value <= spec.max) &&
                  (!spec.integer || value == std::floor(value));
  if (ok) return {};
  return "'" + spec.name + "' = " + Number(value) + " must be " + DescribeRange(spec) + " (" + spec.description + ")";
}

}  // namespace hapsim::core
