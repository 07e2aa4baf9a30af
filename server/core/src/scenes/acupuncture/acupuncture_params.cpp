#include "hapsim/core/scenes/acupuncture/acupuncture_params.h"

#include <cmath>
#include <functional>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace hapsim::core {

namespace {

struct Field {
  std::string key;
  double lo, hi;
  std::function<void(AcupunctureParams&, double)> set;
  bool integer = false;
};

std::vector<Field> Fields() {
  std::vector<Field> f = {
      {"shf_lmax", 1, AcupunctureLimits::kMaxShfLmax, [](auto& p, double v) { p.shf_lmax = static_cast<int>(v); },
       true},
      {"shf_samples", 16, AcupunctureLimits::kMaxShfSamples,
       [](auto& p, double v) { p.shf_samples = static_cast<int>(v); }, true},
      {"net_tension_ratio", 1e-3, 1e4, [](auto& p, double v) { p.net_tension_ratio = v; }},
      {"ring_w_threshold_ratio", 1e-6, 0.5, [](auto& p, double v) { p.ring_w_threshold_ratio = v; }},
      {"springback_eta0", 0, 1, [](auto& p, double v) { p.springback_eta0 = v; }},
      {"springback_eta_rate_per_step", 0, 1, [](auto& p, double v) { p.springback_eta_rate_per_step = v; }},
      {"tunnel_stiffness_N_per_m", 0, 1e5, [](auto& p, double v) { p.tunnel_stiffness_N_per_m = v; }},
      {"render_stiffness_max_N_per_m", 1, 1e5, [](auto& p, double v) { p.render_stiffness_max_N_per_m = v; }},
      {"contact_damping_Ns_per_m", 0, 100, [](auto& p, double v) { p.contact_damping_Ns_per_m = v; }},
      {"patch_size_m", 0.005, 0.2, [](auto& p, double v) { p.patch_size_m = v; }},
      {"patch_grid_nodes", 2, AcupunctureLimits::kMaxPatchGridNodes,
       [](auto& p, double v) { p.patch_grid_nodes = static_cast<int>(v); }, true},
  };
  const char* names[kNumTissueLayers] = {"skin", "fat", "muscle"};
  for (std::size_t i = 0; i < kNumTissueLayers; ++i) {
    const std::string n = names[i];
    f.push_back({n + "_thickness_m", 1e-5, 0.05, [i](auto& p, double v) { p.layers[i].thickness_m = v; }});
    f.push_back({n + "_K_N_per_m", 1e-3, 1e6, [i](auto& p, double v) { p.layers[i].virtual_K_N_per_m = v; }});
    f.push_back({n + "_d_Ns_per_m2", 0, 1e6, [i](auto& p, double v) { p.layers[i].damping_Ns_per_m2 = v; }});
    f.push_back({n + "_rings", 2, AcupunctureLimits::kMaxRings, [i](auto& p, double v) { p.layers[i].rings_w = static_cast<int>(v); }, true});
    f.push_back({n + "_spacing_m", 1e-5, 0.01, [i](auto& p, double v) { p.layers[i].spacing_L_m = v; }});
  }
  return f;
}

}  // namespace

AcupunctureParams ParseAcupunctureParams(const std::map<std::string, double>& params) {
  AcupunctureParams p;
  const std::vector<Field> fields = Fields();
  for (const auto& [key, value] : params) {
    const Field* field = nullptr;
    for (const auto& f : fields)
      if (f.key == key) field = &f;
    if (!field) {
      std::string known;
      for (const auto& f : fields) known += (known.empty() ? "" : ", ") + f.key;
      throw std::invalid_argument("acupuncture: unknown parameter '" + key + "' (known: " + known + ")");
    }
    if (!std::isfinite(value) || value < field->lo || value > field->hi ||
        (field->integer && value != std::floor(value))) {
      std::ostringstream msg;
      msg << "acupuncture: parameter '" << key << "' = " << value << " must be "
          << (field->integer ? "an integer " : "") << "in [" << field->lo << ", " << field->hi << "]";
      throw std::invalid_argument(msg.str());
    }
    field->set(p, value);
  }
  // A least-squares fit of (Lmax+1)^2 coefficients needs at least as many samples.
  const int coefficients = (p.shf_lmax + 1) * (p.shf_lmax + 1);
  if (p.shf_samples < coefficients) {
    std::ostringstream msg;
    msg << "acupuncture: parameter 'shf_samples' = " << p.shf_samples << " must be in [" << coefficients << ", "
        << AcupunctureLimits::kMaxShfSamples << "] for 'shf_lmax' = " << p.shf_lmax
        << " (at least (shf_lmax+1)^2 samples per fit)";
    throw std::invalid_argument(msg.str());
  }
  // Nested layers need room below: the muscle bottom must stay inside the body.
  double total_m = 0.0;
  for (const auto& l : p.layers) total_m += l.thickness_m;
  if (total_m > 0.06)
    throw std::invalid_argument("acupuncture: total layer thickness must be <= 0.06 m (the limb radius is ~0.07 m)");
  return p;
}

}  // namespace hapsim::core
