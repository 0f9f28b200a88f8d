// Pictures for people: a radiance image in the course's 8-bit look, a map
// of |z| per pixel, and PNG files of them. Nothing here decides a verdict.
#pragma once
#include <string>
#include <vector>

#include "grader/src/scoring.h"

namespace grader {

// 8-bit RGB, row 0 at the top.
struct Picture {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;
};

// The course's 8-bit look of a radiance image.
Picture radiance_picture(const ImageBuffer& img);
// |z| per pixel: black through blue to white at `threshold`, red beyond it,
// so that failing pixels stand out.
Picture error_picture(const std::vector<float>& z, int width, int height, double threshold);
// Pictures side by side, `gap` pixels of white between them (same height).
Picture side_by_side(const std::vector<Picture>& pictures, int gap);
// Writes a PNG (through a temporary file). Throws std::runtime_error naming the file.
void save_picture(const std::string& path, const Picture& picture);

}  // namespace grader
