// The grader's image files. PFM (the renders' radiance, the references'
// mean and variance) is read and written by the renderer's own code
// (pt::read_pfm, pt::write_pfm in image_io.h); this is the PNG side: the
// course's 8-bit images and sample-rate images a render writes, and the
// pictures the reports show. Errors throw std::runtime_error naming the file.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "common/image.h"

namespace grader {

using pt::ImageBuffer;

// An 8-bit RGB PNG as an image of byte values (0 to 255 in each channel).
// Throws "<path>: <lodepng's reason>".
ImageBuffer read_png_image(const std::string& path);

// The course's sample-rate colours (pt::rate_to_rgb) back to rates in
// [0, 1], the rate in every channel.
ImageBuffer rate_from_colors(const ImageBuffer& rgb);

// Writes 8-bit RGB bytes, top row first, as a PNG (through a temporary file).
void write_png_rgb(const std::string& path, int width, int height, const std::vector<unsigned char>& rgb);

}  // namespace grader
