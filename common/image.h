// Floating-point image buffers. Pixel (0, 0) is the bottom-left of the image
// (the course's convention); files are flipped when written.
#pragma once
#include <cstdint>
#include <vector>

#include "common/vec3.h"

namespace pt {

struct ImageBuffer {
  int width = 0, height = 0;
  std::vector<Color> pixels;      // linear radiance, row by row from the bottom
  std::vector<uint32_t> samples;  // camera samples taken per pixel

  ImageBuffer() = default;
  ImageBuffer(int w, int h) : width(w), height(h), pixels(size_t(w) * h), samples(size_t(w) * h, 0) {}

  size_t index(int x, int y) const { return size_t(y) * width + x; }
  Color& at(int x, int y) { return pixels[index(x, y)]; }
  const Color& at(int x, int y) const { return pixels[index(x, y)]; }
};

}  // namespace pt
