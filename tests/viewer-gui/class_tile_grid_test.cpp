// The class console's tiles fill the panel in as many columns as fit.
#include <gtest/gtest.h>

#include "hapsim/gui/viewer_panels.h"

namespace hapsim::gui {
namespace {

// The console's panel is 540 px wide; inside its padding and scrollbar
// about 510 px are left, with ImGui's default 8 px item spacing. Two
// columns fit there (250 px tiles in one column left half the panel empty).
TEST(ClassTileGrid, TheConsolePanelHoldsTwoColumnsOfTilesThatFillIt) {
  const TileGrid grid = ClassTileGrid(510.0f, 8.0f);
  EXPECT_EQ(grid.columns, 2);
  EXPECT_FLOAT_EQ(2 * grid.tile_width_px + 8.0f, 510.0f);
}

TEST(ClassTileGrid, ColumnsGrowWithTheWidthAndTilesNeverShrinkBelowTheMinimum) {
  for (float avail = 50.0f; avail <= 3000.0f; avail += 7.0f) {
    const TileGrid grid = ClassTileGrid(avail, 8.0f);
    EXPECT_GE(grid.columns, 1) << avail;
    EXPECT_GE(grid.tile_width_px, TileGrid::kMinTileWidth_px) << avail;
    if (grid.columns > 1) {
      EXPECT_LE(grid.columns * grid.tile_width_px + (grid.columns - 1) * 8.0f, avail + 1e-3f) << avail;
    }
    // One more column would not fit tiles of the minimum width.
    EXPECT_GT((grid.columns + 1) * TileGrid::kMinTileWidth_px + grid.columns * 8.0f, avail) << avail;
  }
}

}  // namespace
}  // namespace hapsim::gui
