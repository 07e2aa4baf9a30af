#include "hapsim/gui/plot_widgets.h"

#include <gtest/gtest.h>

#include "hapsim/gui/viewer_panels.h"

namespace hapsim::gui {
namespace {

TEST(NiceTickStep, IsOneTwoOrFiveTimesAPowerOfTen) {
  EXPECT_DOUBLE_EQ(NiceTickStep(10.0, 5), 2.0);
  EXPECT_DOUBLE_EQ(NiceTickStep(1.0, 4), 0.2);   // 0.25 -> 0.2
  EXPECT_DOUBLE_EQ(NiceTickStep(14.7, 5), 2.0);  // 2.94 -> 2 (5 from 3.5 up)
  EXPECT_DOUBLE_EQ(NiceTickStep(20.0, 5), 5.0);  // 4 -> 5
  EXPECT_DOUBLE_EQ(NiceTickStep(40.0, 5), 10.0); // 8 -> 10
  EXPECT_DOUBLE_EQ(NiceTickStep(0.0, 5), 1.0);   // an empty range still gives a step
}

TEST(ForceAxis, ASmallForceFillsItsPlotAndNoForceKeepsAReadableAxis) {
  EXPECT_NEAR(ForceAxisTop_N(0.05), 0.055, 1e-12);  // a vein pressed lightly: the curve spans 91 % of the plot
  EXPECT_NEAR(ForceAxisTop_N(1.007), 1.1077, 1e-12);
  EXPECT_NEAR(ForceAxisTop_N(0.0), 0.011, 1e-12);
}

}  // namespace
}  // namespace hapsim::gui
