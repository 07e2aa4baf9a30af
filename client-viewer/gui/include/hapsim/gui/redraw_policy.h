// When the window draws. Software rendering without vsync (Xvfb, many
// remote desktops) would otherwise draw flat out — ~175 fps for 60 frames/s
// of data — and take the CPU from the physics server on the same machine.
// So: draw only when something changed (a new frame, the class board,
// input), never more often than max_fps, and, idle, at kIdleRefresh_s so
// the panels' clocks and the answers to button presses still show.
#pragma once

namespace hapsim::gui {

class RedrawPolicy {
 public:
  static constexpr double kIdleRefresh_s = 0.25;
  // ImGui settles hover and active states over a frame or two after input.
  static constexpr int kFramesAfterInput = 3;

  explicit RedrawPolicy(double max_fps) : period_s_(1.0 / max_fps) {}

  double period_s() const { return period_s_; }
  // Seconds before the next draw may happen (0: it may happen now).
  double WaitBefore(double now_s) const {
    const double wait = last_draw_s_ + period_s_ - now_s;
    return wait > 0.0 ? wait : 0.0;
  }
  // Whether to draw at now_s (call once WaitBefore(now_s) is 0): something
  // changed, input came in the last few frames, or the idle refresh is due.
  bool ShouldDraw(double now_s, bool changed, bool input) {
    if (input) frames_after_input_ = kFramesAfterInput;
    return changed || frames_after_input_ > 0 || now_s - last_draw_s_ >= kIdleRefresh_s;
  }
  void Drawn(double now_s) {
    last_draw_s_ = now_s;
    if (frames_after_input_ > 0) --frames_after_input_;
  }

 private:
  double period_s_;
  double last_draw_s_ = -1e9;
  int frames_after_input_ = 0;
};

}  // namespace hapsim::gui
