// Shared by the rendering tests: frames built by hand, an off-screen GL
// context, and pixel helpers.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "hapsim/gui/gl_context.h"
#include "hapsim/gui/image.h"
#include "hapsim/gui/live_scene.h"
#include "hapsim/gui/orbit_camera.h"
#include "hapsim/gui/scene_renderer.h"
#include "hapsim/v1/viewer.pb.h"

namespace hapsim::gui::testing {

// A keyframe of one square [-half, half]^2 at z = 0, as a g x g grid of
// vertices, all triangles of the one part `part`; quantum 10 µm.
inline hapsim::v1::Frame GridKeyframe(int g, double half_m, const std::string& part) {
  hapsim::v1::Frame frame;
  frame.set_seq(0);
  auto* key = frame.mutable_keyframe();
  key->set_quantum_m(1e-5);
  for (int iy = 0; iy < g; ++iy)
    for (int ix = 0; ix < g; ++ix) {
      key->add_positions_q(static_cast<std::int32_t>(std::lround((-half_m + 2 * half_m * ix / (g - 1)) / 1e-5)));
      key->add_positions_q(static_cast<std::int32_t>(std::lround((-half_m + 2 * half_m * iy / (g - 1)) / 1e-5)));
      key->add_positions_q(0);
    }
  for (int iy = 0; iy + 1 < g; ++iy)
    for (int ix = 0; ix + 1 < g; ++ix) {
      const auto v = static_cast<std::uint32_t>(ix + g * iy), gu = static_cast<std::uint32_t>(g);
      for (const std::uint32_t t : {v, v + 1, v + gu + 1, v, v + gu + 1, v + gu}) key->add_triangles(t);
      key->add_triangle_parts(0);
      key->add_triangle_parts(0);
    }
  key->add_part_names(part);
  key->add_layer_names(part);
  key->add_layer_names("muscle");  // a second layer below: skin and fat may be drawn see-through
  key->set_vertex_capacity(static_cast<std::uint32_t>(g * g));
  key->set_triangle_capacity(static_cast<std::uint32_t>(2 * (g - 1) * (g - 1)));
  return frame;
}

inline std::array<int, 3> Pixel(const Image& image, double x, double y) {
  const int xi = static_cast<int>(x), yi = static_cast<int>(y);
  const std::size_t at = 4 * (static_cast<std::size_t>(yi) * static_cast<std::size_t>(image.width) + static_cast<std::size_t>(xi));
  return {image.rgba[at], image.rgba[at + 1], image.rgba[at + 2]};
}

}  // namespace hapsim::gui::testing
