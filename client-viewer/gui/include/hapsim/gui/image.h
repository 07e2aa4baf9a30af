// Pictures read back from the framebuffer, written as PNG (stb_image_write).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace hapsim::gui {

struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgba;  // row 0 is the top row
};

// The currently bound framebuffer's [0, width) x [0, height) pixels.
Image ReadFramebuffer(int width_px, int height_px);
bool WritePng(const std::string& path, const Image& image, std::string* error);

}  // namespace hapsim::gui
