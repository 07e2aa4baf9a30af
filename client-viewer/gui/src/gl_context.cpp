#include "hapsim/gui/gl_context.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <malloc.h>

#include "hapsim/gui/gl.h"

namespace hapsim::gui {

namespace {
std::string glfw_error;
void OnGlfwError(int, const char* description) { glfw_error = description; }

// llvmpipe allocates its per-draw vertex buffers afresh every frame; above
// glibc's mmap threshold each is a new mapping, i.e. page faults for every
// vertex every frame (15-27 % of the time at 50k vertices). Keep them on the
// heap: every user of a context (the viewer, its tests, the benchmark) then
// draws the same way. Process-wide, and harmless for the rest of the viewer.
void KeepDriverBuffersOnTheHeap() {
  mallopt(M_MMAP_THRESHOLD, 256 << 20);
  mallopt(M_TRIM_THRESHOLD, 512 << 20);
}
}  // namespace

std::unique_ptr<GlWindow> GlWindow::Open(int width_px, int height_px, const std::string& title, bool vsync,
                                         std::string* error) {
  KeepDriverBuffersOnTheHeap();
  glfwSetErrorCallback(OnGlfwError);
  if (!glfwInit()) {
    *error = "cannot open a window (" + glfw_error +
             "); without a display use --headless, or ask for files "
             "(--png, --plot-png, --obj, --export), which are then made off screen";
    return nullptr;
  }
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_SAMPLES, 0);  // multisampling quarters llvmpipe's frame rate
  auto window = std::unique_ptr<GlWindow>(new GlWindow());
  window->window_ = glfwCreateWindow(width_px, height_px, title.c_str(), nullptr, nullptr);
  if (!window->window_) {
    *error = "cannot create an OpenGL 3.3 window (" + glfw_error + ")";
    glfwTerminate();
    return nullptr;
  }
  glfwMakeContextCurrent(window->window_);
  glfwSwapInterval(vsync ? 1 : 0);
  return window;
}

GlWindow::~GlWindow() {
  if (window_) glfwDestroyWindow(window_);
  glfwTerminate();
}

bool GlWindow::ShouldClose() const { return glfwWindowShouldClose(window_) != 0; }
void GlWindow::FramebufferSize(int* width_px, int* height_px) const { glfwGetFramebufferSize(window_, width_px, height_px); }
void GlWindow::Swap() { glfwSwapBuffers(window_); }

namespace {

// A surfaceless display (Mesa) with a current OpenGL 3.3 core context; false with *error otherwise.
bool MakeSurfacelessContext(EGLDisplay* display, EGLContext* context, std::string* error) {
  auto get_platform_display =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (!get_platform_display) {
    *error = "EGL has no eglGetPlatformDisplayEXT (need Mesa's libegl-mesa0)";
    return false;
  }
  *display = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  EGLint major = 0, minor = 0;
  if (*display == EGL_NO_DISPLAY || !eglInitialize(*display, &major, &minor)) {
    *error = "cannot initialise a surfaceless EGL display (Mesa's libegl-mesa0 and libgl1-mesa-dri)";
    return false;
  }
  eglBindAPI(EGL_OPENGL_API);
  const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
                               EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  *context = eglCreateContext(*display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes);
  if (*context == EGL_NO_CONTEXT || !eglMakeCurrent(*display, EGL_NO_SURFACE, EGL_NO_SURFACE, *context)) {
    *error = "cannot create an off-screen OpenGL 3.3 core context (EGL error " + std::to_string(eglGetError()) + ")";
    if (*context != EGL_NO_CONTEXT) eglDestroyContext(*display, *context);
    eglTerminate(*display);
    return false;
  }
  return true;
}

// A renderbuffer of `format` attached to the bound framebuffer at `attachment`.
unsigned AttachRenderbuffer(unsigned format, unsigned attachment, int width_px, int height_px) {
  unsigned renderbuffer = 0;
  glGenRenderbuffers(1, &renderbuffer);
  glBindRenderbuffer(GL_RENDERBUFFER, renderbuffer);
  glRenderbufferStorage(GL_RENDERBUFFER, format, width_px, height_px);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, attachment, GL_RENDERBUFFER, renderbuffer);
  return renderbuffer;
}

}  // namespace

std::unique_ptr<HeadlessGl> HeadlessGl::Open(int width_px, int height_px, std::string* error) {
  KeepDriverBuffersOnTheHeap();
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  if (!MakeSurfacelessContext(&display, &context, error)) return nullptr;
  auto gl = std::unique_ptr<HeadlessGl>(new HeadlessGl());
  gl->display_ = display;
  gl->context_ = context;
  gl->width_ = width_px;
  gl->height_ = height_px;
  glGenFramebuffers(1, &gl->framebuffer_);
  glBindFramebuffer(GL_FRAMEBUFFER, gl->framebuffer_);
  gl->colour_ = AttachRenderbuffer(GL_RGBA8, GL_COLOR_ATTACHMENT0, width_px, height_px);
  gl->depth_ = AttachRenderbuffer(GL_DEPTH_COMPONENT24, GL_DEPTH_ATTACHMENT, width_px, height_px);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    *error = "the off-screen framebuffer is incomplete";
    return nullptr;
  }
  return gl;
}

HeadlessGl::~HeadlessGl() {
  if (framebuffer_) glDeleteFramebuffers(1, &framebuffer_);
  if (colour_) glDeleteRenderbuffers(1, &colour_);
  if (depth_) glDeleteRenderbuffers(1, &depth_);
  eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(display_, context_);
  eglTerminate(display_);
}

std::string HeadlessGl::Renderer() const {
  const auto* text = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  return text ? text : "";
}

}  // namespace hapsim::gui
