// The window draws on change, at most max_fps, and at 4 Hz when idle.
#include "hapsim/gui/redraw_policy.h"

#include <gtest/gtest.h>

namespace hapsim::gui {
namespace {

// Runs a window loop for duration_s that wakes every step_s (a frame
// arriving or an event), reporting `changed` and `input` from the given
// functions of time; returns how many times it drew.
template <class Changed, class Input>
int DrawsOver(double duration_s, double step_s, double max_fps, Changed changed, Input input) {
  RedrawPolicy policy(max_fps);
  int draws = 0;
  bool pending_input = false;
  for (double t = 0.0; t < duration_s; t += step_s) {
    pending_input |= input(t);
    if (policy.WaitBefore(t) > 0.0) continue;
    if (!policy.ShouldDraw(t, changed(t), pending_input)) continue;
    pending_input = false;
    policy.Drawn(t);
    ++draws;
  }
  return draws;
}

TEST(RedrawPolicy, NewDataAt1kHzIsDrawnAtMostMaxFps) {
  const int draws = DrawsOver(10.0, 1e-3, 60.0, [](double) { return true; }, [](double) { return false; });
  // Woken every 1 ms, the loop draws every 17 ms (the first wake past 16.7 ms): 588 draws; never above 60/s.
  EXPECT_GE(draws, static_cast<int>(10.0 / 0.017));
  EXPECT_LE(draws, 601);
}

TEST(RedrawPolicy, NewDataAt59HzIsDrawnOncePerFrameOfData) {
  int frames = 0;
  double next_frame = 0.0;
  auto changed = [&](double t) {
    if (t + 1e-9 < next_frame) return false;
    next_frame += 1.0 / 59.0;
    ++frames;
    return true;
  };
  const int draws = DrawsOver(10.0, 1e-3, 60.0, changed, [](double) { return false; });
  EXPECT_GE(frames, 585);
  EXPECT_EQ(draws, frames);  // one draw per frame of data, none in between
}

TEST(RedrawPolicy, AnIdleWindowRedrawsFourTimesASecond) {
  const int draws = DrawsOver(10.0, 1e-3, 60.0, [](double) { return false; }, [](double) { return false; });
  EXPECT_GE(draws, 39);
  EXPECT_LE(draws, 41);
}

TEST(RedrawPolicy, InputIsDrawnWithinOneFrameAndForAFewFramesAfter) {
  RedrawPolicy policy(60.0);
  policy.Drawn(0.0);
  const double t = 0.1;  // idle until a click at 100 ms
  ASSERT_EQ(policy.WaitBefore(t), 0.0);
  EXPECT_TRUE(policy.ShouldDraw(t, false, true));
  policy.Drawn(t);
  int after = 0;
  for (double s = t + policy.period_s(); s < t + 0.2; s += policy.period_s()) {
    if (policy.ShouldDraw(s, false, false)) {
      policy.Drawn(s);
      ++after;
    }
  }
  EXPECT_EQ(after, RedrawPolicy::kFramesAfterInput - 1);
}

}  // namespace
}  // namespace hapsim::gui
