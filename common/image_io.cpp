#include "common/image_io.h"

#include <fcntl.h>
#include <lodepng.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <system_error>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace pt {

uint8_t radiance_to_byte(float L) {
  const double v = std::sqrt(2.0) * double(L);
  if (!(v > 0.0)) return 0;  // also catches NaN
  const double g = std::pow(v, 1.0 / 2.2);
  if (g >= 1.0) return 255;
  return uint8_t(std::floor(255.0 * g));
}

void rate_to_rgb(float rate, uint8_t rgb[3]) {
  float r = std::isfinite(rate) ? std::fmin(std::fmax(rate, 0.0f), 1.0f) : 0.0f;
  float c[3];
  if (r < 0.5f) {  // blue -> green
    const float t = r / 0.5f;
    c[0] = 0; c[1] = t; c[2] = 1 - t;
  } else {  // green -> red
    const float t = (r - 0.5f) / 0.5f;
    c[0] = t; c[1] = 1 - t; c[2] = 0;
  }
  for (int i = 0; i < 3; ++i) rgb[i] = uint8_t(std::lround(255.0f * c[i]));
}

std::string rate_image_path(const std::string& png_path) {
  const std::string ext = ".png";
  if (png_path.size() >= ext.size() &&
      png_path.compare(png_path.size() - ext.size(), ext.size(), ext) == 0)
    return png_path.substr(0, png_path.size() - ext.size()) + "_rate.png";
  return png_path + "_rate.png";
}

std::vector<uint8_t> to_png_bytes(const ImageBuffer& img) {
  std::vector<uint8_t> rgb(size_t(img.width) * img.height * 3);
  for (int y = 0; y < img.height; ++y) {
    const int row = img.height - 1 - y;  // PNG rows go top to bottom
    for (int x = 0; x < img.width; ++x) {
      const Color& c = img.at(x, y);
      uint8_t* p = &rgb[(size_t(row) * img.width + x) * 3];
      p[0] = radiance_to_byte(c.x);
      p[1] = radiance_to_byte(c.y);
      p[2] = radiance_to_byte(c.z);
    }
  }
  return rgb;
}

std::vector<uint8_t> encode_png_rgb(const std::vector<uint8_t>& rgb, int w, int h) {
  std::vector<uint8_t> png;
  const unsigned err = lodepng::encode(png, rgb, unsigned(w), unsigned(h), LCT_RGB, 8);
  if (err) throw std::runtime_error(std::string("PNG encoding failed: ") + lodepng_error_text(err));
  return png;
}

std::vector<uint8_t> encode_png(const ImageBuffer& img) {
  return encode_png_rgb(to_png_bytes(img), img.width, img.height);
}

std::vector<uint8_t> encode_rate_png(const ImageBuffer& img, int max_samples) {
  std::vector<uint8_t> rgb(size_t(img.width) * img.height * 3);
  for (int y = 0; y < img.height; ++y) {
    const int row = img.height - 1 - y;
    for (int x = 0; x < img.width; ++x) {
      const float rate = max_samples > 0 ? float(img.samples[img.index(x, y)]) / float(max_samples) : 0.0f;
      rate_to_rgb(rate, &rgb[(size_t(row) * img.width + x) * 3]);
    }
  }
  return encode_png_rgb(rgb, img.width, img.height);
}

std::vector<uint8_t> encode_pfm(const ImageBuffer& img) {
  // PFM stores rows bottom to top, which is our pixel order; "-1" = little endian.
  const std::string header = "PF\n" + std::to_string(img.width) + " " + std::to_string(img.height) + "\n-1\n";
  std::vector<uint8_t> bytes(header.begin(), header.end());
  const size_t off = bytes.size();
  bytes.resize(off + img.pixels.size() * 3 * sizeof(float));
  static_assert(sizeof(Color) == 3 * sizeof(float), "Color must be three packed floats");
  std::memcpy(bytes.data() + off, img.pixels.data(), img.pixels.size() * sizeof(Color));
  return bytes;
}

namespace {
// Encoding errors name the file they were for.
template <typename F>
std::vector<uint8_t> encoded_for(const std::string& path, F encode) {
  try {
    return encode();
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
}
}  // namespace

void write_png(const std::string& path, const ImageBuffer& img) {
  write_file_atomically(path, encoded_for(path, [&] { return encode_png(img); }));
}

void write_rate_png(const std::string& path, const ImageBuffer& img, int max_samples) {
  write_file_atomically(path, encoded_for(path, [&] { return encode_rate_png(img, max_samples); }));
}

void write_pfm(const std::string& path, const ImageBuffer& img) { write_file_atomically(path, encode_pfm(img)); }

ImageBuffer read_pfm(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open");
  std::string magic;
  int w = 0, h = 0;
  double scale = 0;
  in >> magic >> w >> h >> scale;
  if (!in || magic != "PF") throw std::runtime_error(path + ": not a colour PFM file");
  if (w <= 0 || h <= 0 || w > 65536 || h > 65536) throw std::runtime_error(path + ": bad PFM size");
  if (scale >= 0) throw std::runtime_error(path + ": big-endian PFM is not supported");
  in.get();  // the single whitespace byte after the header
  // All the data must be there before the image is allocated: a header of
  // a few bytes may claim 65536 x 65536 pixels.
  const std::streamoff data_start = in.tellg();
  in.seekg(0, std::ios::end);
  const std::streamoff available = in.tellg() - data_start;
  in.seekg(data_start);
  if (!in || data_start < 0 || available < std::streamoff(size_t(w) * size_t(h) * sizeof(Color)))
    throw std::runtime_error(path + ": PFM data is truncated");
  ImageBuffer img(w, h);
  in.read(reinterpret_cast<char*>(img.pixels.data()), std::streamsize(img.pixels.size() * sizeof(Color)));
  if (!in) throw std::runtime_error(path + ": PFM data is truncated");
  return img;
}

namespace {

std::string temp_name(const std::string& path) { return path + ".tmp." + std::to_string(getpid()); }

// Writes `bytes` to the temporary file of `path` and returns its name.
std::string write_temp(const std::string& path, const std::vector<uint8_t>& bytes) {
  const std::string tmp = temp_name(path);
  FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) throw std::runtime_error(path + ": cannot write: " + std::strerror(errno));
  const size_t n = std::fwrite(bytes.data(), 1, bytes.size(), f);
  const bool ok = n == bytes.size() && std::fflush(f) == 0;
  const int err = errno;
  if (std::fclose(f) != 0 || !ok) {
    const int e = ok ? errno : err;
    std::remove(tmp.c_str());
    throw std::runtime_error(path + ": write failed: " + std::strerror(e));
  }
  return tmp;
}

void rename_into_place(const std::string& tmp, const std::string& path) {
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const int e = errno;
    std::remove(tmp.c_str());
    throw std::runtime_error(path + ": cannot rename into place: " + std::strerror(e));
  }
}

}  // namespace

void write_file_atomically(const std::string& path, const std::vector<uint8_t>& bytes) {
  rename_into_place(write_temp(path, bytes), path);
}

void check_output_path(const std::string& path) {
  namespace fs = std::filesystem;
  if (path.empty()) throw std::runtime_error("an output path is empty");
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);  // follows symbolic links
  if (fs::is_directory(st)) throw std::runtime_error(path + ": is a folder, not a file");
  if (fs::exists(st) && !fs::is_regular_file(st))
    throw std::runtime_error(path + ": exists and is not a regular file; refusing to replace it");
  fs::path dir = fs::path(path).parent_path();
  if (dir.empty()) dir = ".";
  if (!fs::is_directory(dir, ec))
    throw std::runtime_error(path + ": output folder " + dir.string() + " does not exist");
  // The one sure test: create the temporary file the write will use.
  const std::string tmp = temp_name(path);
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) {
    if (errno == EEXIST) return;  // a stale one: the write replaces it
    throw std::runtime_error(path + ": cannot write: " + std::strerror(errno));
  }
  ::close(fd);
  ::unlink(tmp.c_str());
}

AtomicFileSet::~AtomicFileSet() {
  if (committed_) return;
  for (const Pending& p : pending_) std::remove(p.temp.c_str());
}

void AtomicFileSet::add(const std::string& path, const std::vector<uint8_t>& bytes) {
  if (committed_) throw std::logic_error("AtomicFileSet::add after commit");
  for (const Pending& p : pending_)
    if (p.path == path) throw std::runtime_error(path + ": the same output is written twice");
  const std::string tmp = write_temp(path, bytes);
  pending_.push_back({path, tmp});
}

void AtomicFileSet::commit() {
  if (committed_) return;
  for (size_t i = 0; i < pending_.size(); ++i) {
    if (std::rename(pending_[i].temp.c_str(), pending_[i].path.c_str()) != 0) {
      const int e = errno;
      // Undo: the targets renamed so far go, and every temporary left.
      for (size_t j = 0; j < i; ++j) std::remove(pending_[j].path.c_str());
      for (size_t j = i; j < pending_.size(); ++j) std::remove(pending_[j].temp.c_str());
      const std::string path = pending_[i].path;
      pending_.clear();
      throw std::runtime_error(path + ": cannot rename into place: " + std::strerror(e));
    }
  }
  committed_ = true;
}

}  // namespace pt
