// The parameter-table contract, over every scene in the catalogue: every
// default is inside its own range and is what the scene really uses; every
// value outside a range (each side, a fraction for an integer, NaN, inf) and
// every unknown key is refused with a message naming the key; the
// unknown-key message lists every parameter the scene has.
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "hapsim/core/scenes/scene.h"
#include "hapsim/core/scenes/cutting/cutting_params.h"
#include "hapsim/core/scenes/cutting/cutting_scene.h"

namespace hapsim::core {
namespace {

class SceneParams : public ::testing::TestWithParam<std::string> {
 protected:
  SceneDescription Description() const {
    for (auto& s : SceneCatalog())
      if (s.name == GetParam()) return s;
    ADD_FAILURE() << "no scene " << GetParam();
    return {};
  }
};

std::vector<std::string> SceneNames() {
  std::vector<std::string> names;
  for (const auto& scene : SceneCatalog()) names.push_back(scene.name);
  return names;
}

INSTANTIATE_TEST_SUITE_P(Catalog, SceneParams, ::testing::ValuesIn(SceneNames()),
                         [](const auto& test_info) { return test_info.param; });

// The message MakeScene throws for these parameters, or "" if it builds.
std::string Refusal(const std::string& scene, std::map<std::string, double> params) {
  try {
    MakeScene({scene, std::move(params)});
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST_P(SceneParams, EveryParameterIsDescribedAndItsDefaultIsInRange) {
  const SceneDescription scene = Description();
  ASSERT_FALSE(scene.params.empty());
  for (const auto& p : scene.params) {
    SCOPED_TRACE(p.spec.name);
    EXPECT_FALSE(p.spec.unit.empty());
    EXPECT_FALSE(p.spec.description.empty());
    EXPECT_EQ(CheckParamValue(p.spec, p.default_value), "");
    EXPECT_LE(p.spec.min, p.spec.max);
    if (!p.spec.choices.empty()) {
      EXPECT_TRUE(p.spec.integer);
      EXPECT_EQ(static_cast<double>(p.spec.choices.size()), p.spec.max - p.spec.min + 1);
    }
  }
}

TEST_P(SceneParams, TheDescribedDefaultsAreTheDefaultsTheSceneUses) {
  const SceneDescription scene = Description();
  std::map<std::string, double> all_defaults;
  for (const auto& p : scene.params) all_defaults[p.spec.name] = p.default_value;
  const auto implicit = MakeScene({scene.name, {}});
  const auto explicit_defaults = MakeScene({scene.name, all_defaults});
  EXPECT_EQ(implicit->StateHash(), explicit_defaults->StateHash());
  // Stepping both the same way stays identical (parameters that only act
  // later, e.g. in contact, are exercised too).
  ToolInput tool;
  tool.valid = true;
  for (int i = 0; i < 300; ++i) {
    tool.tip_W_m = Eigen::Vector3d(0.001, 0.0005, 0.002 - 1e-5 * i);
    tool.velocity_W_m_per_s = Eigen::Vector3d(0, 0, -0.01);
    implicit->Step(tool, 1e-3);
    explicit_defaults->Step(tool, 1e-3);
  }
  EXPECT_EQ(implicit->StateHash(), explicit_defaults->StateHash());
}

TEST_P(SceneParams, EveryValueOutsideItsRangeIsRefusedNamingTheKey) {
  const SceneDescription scene = Description();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  for (const auto& p : scene.params) {
    const ParamSpec& s = p.spec;
    std::vector<double> bad = {std::nan(""), kInf, -kInf};
    if (std::isfinite(s.min)) bad.push_back(s.min_open ? s.min : std::nextafter(s.min, -kInf));
    if (std::isfinite(s.max)) bad.push_back(s.max_open ? s.max : std::nextafter(s.max, kInf));
    if (s.integer && s.min + 0.5 <= s.max) bad.push_back(s.min + 0.5);
    for (const double v : bad) {
      SCOPED_TRACE(s.name + " = " + std::to_string(v));
      EXPECT_EQ(CheckParamValue(s, v).empty(), false);
      const std::string why = Refusal(scene.name, {{s.name, v}});
      EXPECT_NE(why.find("'" + s.name + "'"), std::string::npos) << why;
      EXPECT_NE(why.find(DescribeRange(s)), std::string::npos) << why;
    }
  }
}

TEST_P(SceneParams, AnUnknownKeyIsRefusedListingEveryKnownParameter) {
  const SceneDescription scene = Description();
  const std::string why = Refusal(scene.name, {{"no_such_parameter", 1.0}});
  EXPECT_NE(why.find("unknown parameter 'no_such_parameter'"), std::string::npos) << why;
  for (const auto& p : scene.params) EXPECT_NE(why.find(p.spec.name), std::string::npos) << p.spec.name << ": " << why;
}

TEST(ParamRange, DescribesEachKindOfBound) {
  EXPECT_EQ(DescribeRange({.name = "n", .min = 3, .max = 101, .integer = true}), "an integer in [3, 101]");
  EXPECT_EQ(DescribeRange({.name = "x", .min = 0, .min_open = true}), "> 0");
  EXPECT_EQ(DescribeRange({.name = "dt", .min = 1e-6}), ">= 1e-06");
  EXPECT_EQ(DescribeRange({.name = "a", .min = 0, .max = 1, .min_open = true}), "in (0, 1]");
  EXPECT_EQ(DescribeRange({.name = "c", .min = 0, .max = 1, .integer = true, .choices = {"off", "on"}}),
            "an integer code 0..1 (0 off, 1 on)");
  const ParamSpec open_both{.name = "p", .min = 0, .max = 1, .min_open = true, .max_open = true};
  EXPECT_EQ(CheckParamValue(open_both, 0.5), "");
  EXPECT_NE(CheckParamValue(open_both, 0.0), "");
  EXPECT_NE(CheckParamValue(open_both, 1.0), "");
}

}  // namespace
}  // namespace hapsim::core

namespace hapsim::core {
namespace {

// Cutting's cross-parameter limits (docs/scene-limits.md#cutting): each is
// refused with a message naming what to change; the largest accepted patch
// still builds a scene whose 1 ms step is stable.
TEST(SceneParams, CuttingLimitsRefuseTooManyNodesAndBadCutGeometry) {
  auto refused = [](std::map<std::string, double> p, const std::string& names) {
    try {
      (void)ParseCuttingParams(p);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what()).find(names) != std::string::npos;
    }
    return false;
  };
  EXPECT_TRUE(refused({{"spacing_m", 0.00048}}, "'spacing_m' give 10584 grid nodes"));
  EXPECT_TRUE(refused({{"sweep_radius_m", 0.0005}}, "'sweep_radius_m' must be >= 'spacing_m'"));
  EXPECT_TRUE(refused({{"segment_length_m", 0.0005}}, "'segment_length_m' must be >= 'spacing_m'"));
  const CuttingParams largest = ParseCuttingParams({{"spacing_m", 0.000485}});  // 125 x 83 = 10375 nodes
  const CuttingScene scene(largest);
  EXPECT_EQ(scene.Skin().nx * scene.Skin().ny, 10375);
}

TEST(SceneParams, CuttingRefusesAnUnstableStepNamingTheParameters) {
  CuttingParams p;
  p.node_mass_kg = 0.001;  // critical step ~0.4 ms < the 1 ms sub-step
  try {
    const CuttingScene scene(p);
    ADD_FAILURE() << "an unstable step was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'node_mass_kg'"), std::string::npos) << e.what();
  }
}

// A megabyte-long unknown key or scene name is refused with a message that
// echoes at most 80 of its characters (docs/reliability.md, gap 7).
TEST(SceneParams, AnUnknownKeyOrSceneIsEchoedBounded) {
  const std::string huge(1 << 20, 'k');
  for (const SceneSpec& spec : {SceneSpec{"tissue_block", {{huge, 1.0}}}, SceneSpec{huge, {}}}) {
    try {
      (void)MakeScene(spec);
      ADD_FAILURE() << "accepted";
    } catch (const std::invalid_argument& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(std::string(80, 'k') + "'"), std::string::npos);
      EXPECT_LT(what.size(), 2000u);
    }
  }
}

}  // namespace
}  // namespace hapsim::core
