#include "hapsim/gui/image.h"

#include <cstring>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#include <stb/stb_image_write.h>

#include "hapsim/gui/gl.h"

namespace hapsim::gui {

Image ReadFramebuffer(int width_px, int height_px) {
  Image image;
  image.width = width_px;
  image.height = height_px;
  const auto row = static_cast<std::size_t>(4 * width_px);
  std::vector<std::uint8_t> bottom_up(row * static_cast<std::size_t>(height_px));
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width_px, height_px, GL_RGBA, GL_UNSIGNED_BYTE, bottom_up.data());
  image.rgba.resize(bottom_up.size());
  for (int y = 0; y < height_px; ++y)  // GL's row 0 is the bottom one
    std::memcpy(&image.rgba[row * static_cast<std::size_t>(y)],
                &bottom_up[row * static_cast<std::size_t>(height_px - 1 - y)], row);
  return image;
}

bool WritePng(const std::string& path, const Image& image, std::string* error) {
  if (image.width <= 0 || image.height <= 0) {
    *error = "nothing to write to " + path;
    return false;
  }
  if (!stbi_write_png(path.c_str(), image.width, image.height, 4, image.rgba.data(), 4 * image.width)) {
    *error = "cannot write " + path;
    return false;
  }
  return true;
}

}  // namespace hapsim::gui
