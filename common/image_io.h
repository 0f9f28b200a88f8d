// Writing and reading images: the course's 8-bit PNG look, the sample-rate
// PNG, and PFM (32-bit float, for grading). Every write goes to a temporary
// file beside the target and is renamed into place, so a killed run never
// leaves a half-written file; AtomicFileSet writes several files all or
// nothing. Errors throw std::runtime_error naming the file.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "common/image.h"

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
// Those bytes (w x h, top row first) as a PNG file's.
std::vector<uint8_t> encode_png_rgb(const std::vector<uint8_t>& rgb, int w, int h);

// The files' bytes: an 8-bit PNG, the sample-rate PNG (rate = samples /
// max_samples per pixel), and a little-endian colour PFM.
std::vector<uint8_t> encode_png(const ImageBuffer& img);
std::vector<uint8_t> encode_rate_png(const ImageBuffer& img, int max_samples);
std::vector<uint8_t> encode_pfm(const ImageBuffer& img);

void write_png(const std::string& path, const ImageBuffer& img);
// rate = samples / max_samples per pixel.
void write_rate_png(const std::string& path, const ImageBuffer& img, int max_samples);
void write_pfm(const std::string& path, const ImageBuffer& img);
// Reads a colour PFM written by write_pfm (or any little-endian "PF" file).
ImageBuffer read_pfm(const std::string& path);

// Writes `bytes` to `path` through a temporary file and a rename.
void write_file_atomically(const std::string& path, const std::vector<uint8_t>& bytes);

// Throws std::runtime_error naming `path` unless a file can be written
// there the way write_file_atomically does it: its folder exists, a
// temporary file can be created in it (tried, then removed), and `path` is
// not a folder or anything else that is not a regular file. Called for
// every output before a render, so that a long render is not wasted.
void check_output_path(const std::string& path);

// Several files written as one, all or nothing. add() writes each file to
// a temporary name beside its target at once (so that only one file's bytes
// need be in memory); commit() renames them all into place. If an add() or
// the commit fails, or the set is destroyed without a commit, the temporary
// files are removed and so are the targets already renamed by the commit:
// no output is left behind unless every one of them was written.
class AtomicFileSet {
 public:
  AtomicFileSet() = default;
  AtomicFileSet(const AtomicFileSet&) = delete;
  AtomicFileSet& operator=(const AtomicFileSet&) = delete;
  ~AtomicFileSet();

  void add(const std::string& path, const std::vector<uint8_t>& bytes);
  void commit();

 private:
  struct Pending {
    std::string path, temp;
  };
  std::vector<Pending> pending_;
  bool committed_ = false;
};

}  // namespace pt
