#include "grader/src/image_files.h"

#include <lodepng.h>

#include <stdexcept>

#include "common/image_io.h"

namespace grader {

ImageBuffer read_png_image(const std::string& path) {
  std::vector<unsigned char> rgb;
  unsigned w = 0, h = 0;
  const unsigned err = lodepng::decode(rgb, w, h, path, LCT_RGB, 8);
  if (err) throw std::runtime_error(path + ": " + lodepng_error_text(err));
  ImageBuffer img{int(w), int(h)};
  for (int row = 0; row < img.height; ++row)  // PNG rows go top to bottom
    for (int x = 0; x < img.width; ++x) {
      const unsigned char* p = &rgb[(size_t(row) * w + size_t(x)) * 3];
      img.at(x, img.height - 1 - row) = pt::Color(float(p[0]), float(p[1]), float(p[2]));
    }
  return img;
}

ImageBuffer rate_from_colors(const ImageBuffer& rgb) {
  ImageBuffer rate(rgb.width, rgb.height);
  for (size_t i = 0; i < rgb.pixels.size(); ++i) {
    const float r = rgb.pixels[i].x, g = rgb.pixels[i].y, b = rgb.pixels[i].z;
    // Blue -> green covers [0, 0.5], green -> red covers [0.5, 1].
    float v = 0;
    if (r > 0 && r + g > 0) v = 0.5f + 0.5f * r / (r + g);
    else if (g + b > 0) v = 0.5f * g / (g + b);
    rate.pixels[i] = pt::Color(v);
  }
  return rate;
}

void write_png_rgb(const std::string& path, int width, int height, const std::vector<unsigned char>& rgb) {
  std::vector<unsigned char> png;
  const unsigned err = lodepng::encode(png, rgb, unsigned(width), unsigned(height), LCT_RGB, 8);
  if (err) throw std::runtime_error(path + ": " + lodepng_error_text(err));
  pt::write_file_atomically(path, std::vector<uint8_t>(png.begin(), png.end()));
}

}  // namespace grader
