// Where the viewer draws: an on-screen GLFW window, or an off-screen
// framebuffer in a surfaceless EGL context (Mesa's llvmpipe when there is
// no GPU) for --png and tests, which needs no X display at all. Both give
// an OpenGL 3.3 core context, current on the calling thread.
#pragma once
#include <memory>
#include <string>

struct GLFWwindow;

namespace hapsim::gui {

class GlWindow {
 public:
  // Null with *error set when there is no display or no GL 3.3.
  static std::unique_ptr<GlWindow> Open(int width_px, int height_px, const std::string& title, bool vsync,
                                        std::string* error);
  ~GlWindow();
  GLFWwindow* handle() const { return window_; }
  bool ShouldClose() const;
  void FramebufferSize(int* width_px, int* height_px) const;
  void Swap();

 private:
  GLFWwindow* window_ = nullptr;
};

class HeadlessGl {
 public:
  // An EGL surfaceless context with a width x height RGBA8 + depth
  // framebuffer bound for drawing. Null with *error set when EGL or GL 3.3
  // is not available.
  static std::unique_ptr<HeadlessGl> Open(int width_px, int height_px, std::string* error);
  ~HeadlessGl();
  int width() const { return width_; }
  int height() const { return height_; }
  unsigned framebuffer() const { return framebuffer_; }  // draw here (GL name)
  std::string Renderer() const;  // e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"

 private:
  HeadlessGl() = default;
  void* display_ = nullptr;
  void* context_ = nullptr;
  unsigned framebuffer_ = 0, colour_ = 0, depth_ = 0;
  int width_ = 0, height_ = 0;
};

}  // namespace hapsim::gui
