// Cost limits on scene parameters (docs/scene-limits.md): a client cannot
// ask for a build or a tick the server cannot afford. Beyond a limit,
// MakeScene throws std::invalid_argument naming the parameter and its range.
#include <algorithm>
#include <map>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "hapsim/core/scenes/acupuncture/acupuncture_params.h"
#include "hapsim/core/scenes/scene.h"
#include "hapsim/core/scenes/tissue_block/tissue_block.h"

namespace hapsim::core {
namespace {

// The message of the std::invalid_argument MakeScene throws ("" if none).
std::string Rejection(const std::string& scene, const std::map<std::string, double>& params) {
  try {
    MakeScene({scene, params});
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(SceneLimits, AcupunctureShDegreeAboveSixteenIsRejectedWithItsRange) {
  const std::string why = Rejection("acupuncture", {{"shf_lmax", 17}});
  EXPECT_NE(why.find("'shf_lmax'"), std::string::npos) << why;
  EXPECT_NE(why.find("[1, 16]"), std::string::npos) << why;
}

TEST(SceneLimits, AcupunctureMinuteLongFitOnceAcceptedIsRejected) {
  // Took about a minute to build before the scene limits existed.
  EXPECT_NE(Rejection("acupuncture", {{"shf_lmax", 30}, {"shf_samples", 20000}}), "");
}

TEST(SceneLimits, AcupunctureSampleCountAboveLimitIsRejectedWithItsRange) {
  const std::string why = Rejection("acupuncture", {{"shf_samples", AcupunctureLimits::kMaxShfSamples + 1}});
  EXPECT_NE(why.find("'shf_samples'"), std::string::npos) << why;
  EXPECT_NE(why.find("[16, 3000]"), std::string::npos) << why;
}

TEST(SceneLimits, AcupunctureFewerSamplesThanCoefficientsNameBothParameters) {
  const std::string why = Rejection("acupuncture", {{"shf_lmax", 10}, {"shf_samples", 120}});  // needs 121
  EXPECT_NE(why.find("'shf_samples'"), std::string::npos) << why;
  EXPECT_NE(why.find("[121, 3000]"), std::string::npos) << why;
  EXPECT_NE(why.find("'shf_lmax' = 10"), std::string::npos) << why;
}

TEST(SceneLimits, AcupuncturePatchAndRingSizesAboveLimitAreRejected) {
  EXPECT_NE(Rejection("acupuncture", {{"patch_grid_nodes", AcupunctureLimits::kMaxPatchGridNodes + 1}})
                .find("[2, 101]"),
            std::string::npos);
  EXPECT_NE(Rejection("acupuncture", {{"muscle_rings", AcupunctureLimits::kMaxRings + 1}}).find("'muscle_rings'"),
            std::string::npos);
}

TEST(SceneLimits, AcupunctureLargestSizesTogetherAreAccepted) {
  EXPECT_EQ(Rejection("acupuncture", {{"shf_lmax", AcupunctureLimits::kMaxShfLmax},
                                      {"shf_samples", 289},  // (16 + 1)^2: the cheapest fit of that degree
                                      {"patch_grid_nodes", AcupunctureLimits::kMaxPatchGridNodes},
                                      {"skin_rings", AcupunctureLimits::kMaxRings}}),
            "");
}

TEST(SceneLimits, TissueBlockGridAboveLimitIsRejectedWithItsRange) {
  const std::string why = Rejection("tissue_block", {{"grid_nodes", TissueBlockLimits::kMaxGridNodes + 1}});
  EXPECT_NE(why.find("'grid_nodes'"), std::string::npos) << why;
  EXPECT_NE(why.find("[3, 101]"), std::string::npos) << why;
  EXPECT_EQ(Rejection("tissue_block", {{"grid_nodes", TissueBlockLimits::kMaxGridNodes}}), "");
}

TEST(SceneLimits, TissueBlockSubstepBelowOneMicrosecondIsRejected) {
  const std::string why = Rejection("tissue_block", {{"dt_s", 0.5e-6}});
  EXPECT_NE(why.find("'dt_s'"), std::string::npos) << why;
  EXPECT_NE(why.find(">= 1e-06"), std::string::npos) << why;
}

TEST(SceneLimits, TissueBlockDefaultCostsOneUpdatePerNode) {
  EXPECT_DOUBLE_EQ(TissueBlockStepCost(TissueBlockParams{}), 21.0 * 21.0);
}

TEST(SceneLimits, TissueBlockCostlyCombinationNamesEveryParameterOfTheCost) {
  // Each value alone is in range; together: 31^2 nodes x 26 (backward Euler) > 12000.
  const std::string why = Rejection("tissue_block", {{"grid_nodes", 31}, {"integrator", 5}});
  for (const char* key : {"'grid_nodes' = 31", "'dt_s'", "'integrator' = backward_euler", "'local_update_hops'"})
    EXPECT_NE(why.find(key), std::string::npos) << key << " not in: " << why;
  EXPECT_NE(why.find("the limit is 12000"), std::string::npos) << why;
}

TEST(SceneLimits, TissueBlockEveryIntegratorRunsOnTheDefaultGrid) {
  for (int code = 0; code <= 5; ++code) {
    // Explicit schemes need a sub-step below their critical step (0.125 ms).
    const double dt_s = code == 1 || code >= 3 ? 1e-3 : 1e-4;
    EXPECT_EQ(Rejection("tissue_block", {{"integrator", code}, {"dt_s", dt_s}}), "") << "integrator " << code;
  }
}

TEST(SceneLimits, TissueBlockSubstepsAndLocalRegionCountInTheCost) {
  TissueBlockParams p;
  p.dt_s = 1e-4;  // 10 sub-steps per 1 ms
  EXPECT_DOUBLE_EQ(TissueBlockStepCost(p), 10 * 441.0);
  p.dt_s = 1e-3;
  p.local_update_hops = 2;  // 5 x 5 region
  EXPECT_DOUBLE_EQ(TissueBlockStepCost(p), 1.15 * 441.0 + 8.0 * 25.0);
}

TEST(SceneLimits, TissueBlockTruncatedImplicitSolveOfAStiffTissueStaysStable) {
  // 1000x the default spring stiffness: backward Euler needs ~100 CG
  // iterations per step and gets TissueBlockLimits::kMaxCgIterations (20).
  auto scene = MakeScene({"tissue_block",
                          {{"integrator", 5}, {"spring_stiffness_N_per_m", 1.6e5}, {"shear_stiffness_N_per_m", 1.6e5}}});
  ToolInput tool;
  tool.valid = true;
  for (int k = 0; k < 2000; ++k) {  // press 5 mm in 1 s, then hold
    tool.tip_W_m = Eigen::Vector3d(1.1e-3, 0.7e-3, 1e-3 - 6e-3 * std::min(1.0, k / 1000.0));
    scene->Step(tool, 1e-3);
  }
  EXPECT_EQ(scene->Status().numerical_resets, 0u);
  EXPECT_TRUE(scene->Vertices_m().allFinite());
  EXPECT_GT(scene->ToolForce_W_N().z(), 0.1);  // still pushes back
}

}  // namespace
}  // namespace hapsim::core
