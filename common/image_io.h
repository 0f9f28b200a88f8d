// Writing and reading images: the course's 8-bit PNG look, the sample-rate
// PNG, and PFM (32-bit float, for grading). Every write goes to a temporary
// file beside the target and is renamed into place, so a killed run never
// leaves a half-written file. Errors throw std::runtime_error naming the file.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "image.h"

namespace pt {

// The course's 8-bit conversion: floor(255 * clamp((sqrt(2) L)^(1/2.2), 0, 1)),
// NaN and negative values give 0.
uint8_t radiance_to_byte(float L);

// The sample-rate colour map: rate 0 blue, 0.5 green, 1 red, linear between.
void rate_to_rgb(float rate, uint8_t rgb[3]);

// "out/img.png" -> "out/img_rate.png" (the course's name for the rate image).
std::string rate_image_path(const std::string& png_path);

// 8-bit RGB bytes of `img`, top row first.
std::vector<uint8_t> to_png_bytes(const ImageBuffer& img);

void write_png(const std::string& path, const ImageBuffer& img);
// rate = samples / max_samples per pixel.
void write_rate_png(const std::string& path, const ImageBuffer& img, int max_samples);
void write_pfm(const std::string& path, const ImageBuffer& img);
// Reads a colour PFM written by write_pfm (or any little-endian "PF" file).
ImageBuffer read_pfm(const std::string& path);

// Writes `bytes` to `path` through a temporary file and a rename.
void write_file_atomically(const std::string& path, const std::vector<uint8_t>& bytes);

}  // namespace pt
