// One parameter table per scene: every parameter declared once, with its
// name, unit, valid range, whether it is an integer, a one-line description
// and where it lives in the scene's Params struct (its default is what that
// struct holds). Parsing, the range and unknown-key errors, the catalogue
// (SceneCatalog(): ListScenes, hapsim-ctl scenes, hapsim-server --help) all
// come from the table, so they cannot drift apart.
#pragma once
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace hapsim::core {

inline constexpr double kNoLimit = std::numeric_limits<double>::infinity();

// What a parameter accepts. Bounds are inclusive unless marked open; an
// infinite bound is no bound. Integer parameters take whole numbers only;
// `choices`, when given, names the integer codes min, min+1, ..., max.
struct ParamSpec {
  std::string name;         // key in SceneSpec::params, SI with the unit in the name where it has one
  std::string unit;         // "m", "N/m", "s", "kg", "1" (dimensionless), "count", "code"
  double min = -kNoLimit;
  double max = kNoLimit;
  bool min_open = false;    // true: value must be > min
  bool max_open = false;    // true: value must be < max
  bool integer = false;
  std::string description;  // one line
  std::vector<std::string> choices;
};

// A parameter as a client sees it: its spec and its default.
struct ParamInfo {
  ParamSpec spec;
  double default_value = 0.0;
};

// "in [3, 101]", "> 0", ">= 1e-06", "in (0, 1]", "an integer code 0..5 (a, b, ...)".
std::string DescribeRange(const ParamSpec& spec);
// One line per parameter: name, default, unit, range, description (for
// --help and logs).
std::string FormatParams(const std::vector<ParamInfo>& params, const std::string& indent = "  ");
// Empty if `value` is acceptable, else why not: "'grid_nodes' = 2.5 must be an integer in [3, 101]".
std::string CheckParamValue(const ParamSpec& spec, double value);

// The table of one scene's parameters, bound to its Params struct P.
template <class P>
class ParamTable {
 public:
  using Get = std::function<double(const P&)>;
  using Set = std::function<void(P&, double)>;

  explicit ParamTable(std::string scene) : scene_(std::move(scene)) {}

  ParamTable& Add(ParamSpec spec, Get get, Set set) {
    entries_.push_back({std::move(spec), std::move(get), std::move(set)});
    return *this;
  }
  // A plain double member.
  ParamTable& Add(ParamSpec spec, double P::*member) {
    return Add(std::move(spec), [member](const P& p) { return p.*member; },
               [member](P& p, double v) { p.*member = v; });
  }
  // A plain int member (the spec must be integer).
  ParamTable& Add(ParamSpec spec, int P::*member) {
    spec.integer = true;
    return Add(std::move(spec), [member](const P& p) { return static_cast<double>(p.*member); },
               [member](P& p, double v) { p.*member = static_cast<int>(v); });
  }

  // Defaults with `values` applied. Throws std::invalid_argument naming the
  // scene and the key: an unknown key (listing every known one) or a value
  // outside its range. Cross-parameter rules are the scene's own, after this.
  P Parse(const std::map<std::string, double>& values) const {
    P p{};
    for (const auto& [key, value] : values) {
      const Entry* e = Find(key);
      // The key is echoed cut to 80 characters: a client's megabyte of
      // garbage must not come back as a megabyte of status message.
      if (!e) throw std::invalid_argument(scene_ + ": unknown parameter '" + key.substr(0, 80) + "' (known: " + KnownKeys() + ")");
      if (const std::string why = CheckParamValue(e->spec, value); !why.empty()) {
        throw std::invalid_argument(scene_ + ": parameter " + why);
      }
      e->set(p, value);
    }
    return p;
  }

  std::vector<ParamInfo> Describe() const {
    const P defaults{};
    std::vector<ParamInfo> out;
    out.reserve(entries_.size());
    for (const auto& e : entries_) out.push_back({e.spec, e.get(defaults)});
    return out;
  }

 private:
  struct Entry {
    ParamSpec spec;
    Get get;
    Set set;
  };
  const Entry* Find(const std::string& key) const {
    for (const auto& e : entries_)
      if (e.spec.name == key) return &e;
    return nullptr;
  }
  std::string KnownKeys() const {
    std::string known;
    for (const auto& e : entries_) known += (known.empty() ? "" : ", ") + e.spec.name;
    return known;
  }

  std::string scene_;
  std::vector<Entry> entries_;
};

}  // namespace hapsim::core
