#include "common/environment.h"

#include <ImfChannelList.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfRgbaFile.h>
#include <ImfStdIO.h>
#include <ImfTileDescription.h>
#include <ImfVersion.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <new>
#include <stdexcept>
#include <system_error>
#include <vector>

#include "common/samplers.h"

namespace pt {

namespace {

// The largest map accepted, in texels (8192 x 4096: 400 MB of texels).
constexpr int64_t kMaxTexels = int64_t(1) << 25;
// The largest tile of a tiled file, in texels (e.g. 2048 x 2048).
constexpr int64_t kMaxTileTexels = int64_t(1) << 22;

// A texel index from a continuous coordinate in [0, n); NaN and values out
// of range (a direction with NaN or infinite components) clamp to the map.
int texel_index(float v, int n) {
  if (!(v >= 0.0f)) return 0;  // also NaN
  if (v >= float(n)) return n - 1;
  return std::min(int(v), n - 1);
}

// Messages are one line, whatever the library or the file put in them.
std::string one_line(std::string s) {
  for (char& c : s)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = ' ';
  return s;
}

// The most a compression scheme can shrink pixel data, bounded from above
// (zlib at best about 1032:1; PIZ's Huffman runs less; B44 has a fixed
// rate). DWA, lossy, can shrink a flat image by tens of thousands, so its
// bound (and an unknown scheme's) only catches the absurd. A file smaller
// than its pixels divided by this cannot hold them.
double max_compression_ratio(Imf::Compression c) {
  switch (c) {
    case Imf::NO_COMPRESSION: return 1;
    case Imf::RLE_COMPRESSION: return 64;      // a run of up to 128 bytes in 2
    case Imf::B44_COMPRESSION:
    case Imf::B44A_COMPRESSION: return 16;     // 32 bytes in 14, flat blocks in 3
    case Imf::ZIPS_COMPRESSION:
    case Imf::ZIP_COMPRESSION:
    case Imf::PIZ_COMPRESSION:
    case Imf::PXR24_COMPRESSION: return 2048;
    default: return 1 << 20;
  }
}

// Scan lines per chunk (each chunk has an 8-byte entry in the file's table).
int lines_per_chunk(Imf::Compression c) {
  switch (c) {
    case Imf::ZIP_COMPRESSION:
    case Imf::PXR24_COMPRESSION: return 16;
    case Imf::PIZ_COMPRESSION:
    case Imf::B44_COMPRESSION:
    case Imf::B44A_COMPRESSION:
    case Imf::DWAA_COMPRESSION: return 32;
    case Imf::DWAB_COMPRESSION: return 256;
    default: return 1;
  }
}

int64_t ceil_div(int64_t a, int64_t b) { return (a + b - 1) / b; }

// Walks the header's attributes (name, type, size, value) and refuses one
// whose size exceeds what is left of the file or disagrees with its type.
// OpenEXR would allocate a size it reads (up to 2 GB for a string, more for
// a preview image) before finding the file short, and it reads values of
// fixed-size types whatever their stated size, so that an attribute of the
// wrong size puts it out of step with the file.
void check_attributes(const std::string& path, uint64_t file_size) {
  static const std::pair<const char*, int32_t> kFixed[] = {
      {"box2i", 16}, {"box2f", 16},  {"chromaticities", 32}, {"compression", 1}, {"deepImageState", 1},
      {"double", 8}, {"envmap", 1},  {"float", 4},           {"int", 4},         {"keycode", 28},
      {"lineOrder", 1}, {"m33f", 36}, {"m33d", 72},          {"m44f", 64},       {"m44d", 128},
      {"rational", 8}, {"tiledesc", 9}, {"timecode", 8},     {"v2i", 8},         {"v2f", 8},
      {"v2d", 16},   {"v3i", 12},    {"v3f", 12},            {"v3d", 24}};
  std::ifstream in(path, std::ios::binary);
  in.seekg(8);  // magic number and version
  auto read_name = [&](std::string* out) {
    out->clear();
    for (char c; in.get(c);) {
      if (c == '\0') return true;
      if (out->size() >= 255) return false;
      *out += c;
    }
    return false;
  };
  auto le32 = [](const char* p) {
    return uint32_t(uint8_t(p[0])) | uint32_t(uint8_t(p[1])) << 8 | uint32_t(uint8_t(p[2])) << 16 |
           uint32_t(uint8_t(p[3])) << 24;
  };
  for (int count = 0;; ++count) {
    std::string name, type;
    if (!read_name(&name)) throw std::runtime_error("the header ends early or has an over-long attribute name");
    if (name.empty()) return;  // the end of the header
    if (count >= 10000) throw std::runtime_error("the header has too many attributes");
    if (!read_name(&type)) throw std::runtime_error("the header ends early in attribute " + name);
    char b[4];
    if (!in.read(b, 4)) throw std::runtime_error("the header ends early in attribute " + name);
    const int32_t size = int32_t(le32(b));
    const std::streamoff at = in.tellg();
    const std::string what = "header attribute " + name + " (" + type + ")";
    if (size < 0 || at < 0 || uint64_t(size) > file_size - uint64_t(at))
      throw std::runtime_error(what + " claims " + std::to_string(size) + " bytes, more than the file holds");
    bool checked = false;
    for (const auto& [t, n] : kFixed)
      if (type == t) {
        if (size != n)
          throw std::runtime_error(what + " has " + std::to_string(size) + " bytes, not " + std::to_string(n));
        checked = true;
      }
    if (!checked && (type == "chlist" || type == "stringvector" || type == "preview")) {
      std::vector<char> v(size_t(size) + 1, '\0');  // the extra byte ends an unterminated name
      if (!in.read(v.data(), size)) throw std::runtime_error("the header ends early in attribute " + name);
      bool ok = false;
      size_t p = 0;
      const size_t n = size_t(size);
      if (type == "chlist") {  // entries of name, NUL and 16 bytes; an empty name ends the list
        while (p < n) {
          const size_t len = std::strlen(&v[p]);
          if (len > 255) break;
          if (len == 0) {
            ok = p + 1 == n;
            break;
          }
          p += len + 1 + 16;
        }
      } else if (type == "stringvector") {  // entries of a length and that many bytes
        while (p + 4 <= n) {
          const uint32_t len = le32(&v[p]);
          if (len > n - p - 4) break;
          p += 4 + len;
        }
        ok = p == n;
      } else {  // preview: width, height and 4 bytes per pixel
        ok = n >= 8 && uint64_t(n) == 8 + 4 * uint64_t(le32(&v[0])) * uint64_t(le32(&v[4]));
      }
      if (!ok) throw std::runtime_error(what + " is malformed");
      continue;
    }
    if (type == "idmanifest") throw std::runtime_error("ID manifests are not supported");
    in.seekg(size, std::ios::cur);
  }
}

// Reads the header alone and refuses a file whose image is too large, or
// larger than the file can hold, before OpenEXR sets anything up for it.
// Returns the data window's size.
void check_header(const std::string& path, uint64_t file_size, int64_t* width, int64_t* height) {
  Imf::StdIFStream is(path.c_str());
  char head[8];
  is.read(head, 8);
  auto le32 = [&](int at) {
    return int32_t(uint32_t(uint8_t(head[at])) | uint32_t(uint8_t(head[at + 1])) << 8 |
                   uint32_t(uint8_t(head[at + 2])) << 16 | uint32_t(uint8_t(head[at + 3])) << 24);
  };
  if (le32(0) != Imf::MAGIC) throw std::runtime_error("not an OpenEXR file");
  int version = le32(4);
  if (Imf::getVersion(version) != Imf::EXR_VERSION || !Imf::supportsFlags(Imf::getFlags(version)))
    throw std::runtime_error("unsupported OpenEXR version " + std::to_string(Imf::getVersion(version)));
  if (Imf::isMultiPart(version) || Imf::isNonImage(version))
    throw std::runtime_error("multi-part and deep OpenEXR files are not supported");
  check_attributes(path, file_size);
  Imf::Header header;
  header.readFrom(is, version);
  const bool tiled = Imf::isTiled(version);
  header.sanityCheck(tiled);

  const Imath::Box2i dw = header.dataWindow();
  const int64_t w = int64_t(dw.max.x) - dw.min.x + 1, h = int64_t(dw.max.y) - dw.min.y + 1;
  const std::string size = std::to_string(w) + "x" + std::to_string(h);
  if (w < 1 || h < 1) throw std::runtime_error("the header gives an empty image (" + size + ")");
  if (w * h > kMaxTexels)
    throw std::runtime_error("the header claims " + size + " pixels; at most " + std::to_string(kMaxTexels) +
                             " (e.g. 8192x4096) are accepted");

  // The table of chunk offsets alone takes 8 bytes per chunk.
  int64_t chunks = 0;
  if (tiled) {
    const Imf::TileDescription& td = header.tileDescription();
    // OpenEXR sets up buffers for whole tiles, however small the image.
    if (td.xSize < 1 || td.ySize < 1 || int64_t(td.xSize) * int64_t(td.ySize) > kMaxTileTexels)
      throw std::runtime_error("tiles of " + std::to_string(td.xSize) + "x" + std::to_string(td.ySize) +
                               " pixels are not supported (at most " + std::to_string(kMaxTileTexels) + " pixels)");
    chunks = ceil_div(w, std::max<int64_t>(1, td.xSize)) * ceil_div(h, std::max<int64_t>(1, td.ySize));
  } else {
    chunks = ceil_div(h, lines_per_chunk(header.compression()));
  }
  // And the pixels, compressed at best by the scheme's largest ratio.
  double raw = 0;
  for (Imf::ChannelList::ConstIterator c = header.channels().begin(); c != header.channels().end(); ++c) {
    const Imf::Channel& ch = c.channel();
    const double bytes = ch.type == Imf::HALF ? 2 : 4;
    raw += double(ceil_div(w, std::max(1, ch.xSampling))) * double(ceil_div(h, std::max(1, ch.ySampling))) * bytes;
  }
  const double least = 8.0 * double(chunks) + raw / max_compression_ratio(header.compression());
  if (double(file_size) < least)
    throw std::runtime_error("the header claims " + size + " pixels, which cannot fit in a file of " +
                             std::to_string(file_size) + " bytes");
  *width = w;
  *height = h;
}

}  // namespace

void direction_to_angles(const Vec3& d, float* theta, float* phi) {
  *theta = std::acos(std::fmax(-1.0f, std::fmin(1.0f, d.y)));
  *phi = std::atan2(-d.z, d.x) + kPi;  // [0, 2 pi]
}

Vec3 angles_to_direction(float theta, float phi) {
  const float s = std::sin(theta);
  return Vec3(-std::cos(phi) * s, std::cos(theta), std::sin(phi) * s);
}

void EnvironmentMap::texel_of(const Vec3& d, int* x, int* y) const {
  float theta = 0, phi = 0;
  direction_to_angles(d, &theta, &phi);
  *x = texel_index(phi / (2 * kPi) * float(width), width);
  *y = texel_index(theta / kPi * float(height), height);
}

Color EnvironmentMap::lookup(const Vec3& d) const {
  if (texels.empty()) return Color(0.0f);
  int x = 0, y = 0;
  texel_of(d, &x, &y);
  return texels[size_t(y) * size_t(width) + size_t(x)];
}

EnvironmentMap load_environment_map(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw std::runtime_error(path + ": no such environment map");
  const uintmax_t file_size = std::filesystem::file_size(path, ec);
  if (ec) throw std::runtime_error(path + ": cannot read the environment map: " + ec.message());
  EnvironmentMap env;
  try {
    int64_t w = 0, h = 0;
    check_header(path, file_size, &w, &h);
    Imf::RgbaInputFile file(path.c_str());
    const Imath::Box2i dw = file.dataWindow();
    if (int64_t(dw.max.x) - dw.min.x + 1 != w || int64_t(dw.max.y) - dw.min.y + 1 != h)
      throw std::runtime_error("the header changed while reading");
    // Read in strips of rows of at most about 16 MB.
    const int64_t strip_rows = std::max<int64_t>(1, std::min<int64_t>(h, (int64_t(1) << 21) / w));
    std::vector<Imf::Rgba> strip(size_t(strip_rows * w));
    for (int64_t y0 = 0; y0 < h; y0 += strip_rows) {
      const int64_t rows = std::min(strip_rows, h - y0);
      // OpenEXR addresses the buffer by absolute pixel coordinates; the
      // origin it wants lies outside the strip (computed without pointer
      // arithmetic outside the array).
      const uint64_t origin = uint64_t(int64_t(dw.min.x) + (int64_t(dw.min.y) + y0) * w) * sizeof(Imf::Rgba);
      file.setFrameBuffer(reinterpret_cast<Imf::Rgba*>(reinterpret_cast<uintptr_t>(strip.data()) - origin), 1,
                          size_t(w));
      file.readPixels(int(dw.min.y + y0), int(dw.min.y + y0 + rows - 1));
      // The whole map's memory is taken once the first rows have been read
      // (a file whose data is missing costs no more than a strip).
      if (y0 == 0) env.texels.reserve(size_t(w) * size_t(h));
      for (int64_t r = 0; r < rows; ++r)
        for (int64_t x = 0; x < w; ++x) {
          const Imf::Rgba& p = strip[size_t(r * w + x)];
          const Color c(float(p.r), float(p.g), float(p.b));
          if (!is_finite(c) || c.x < 0 || c.y < 0 || c.z < 0)
            throw std::runtime_error("texel (" + std::to_string(x) + ", " + std::to_string(y0 + r) +
                                     ") is negative or not finite");
          env.texels.push_back(c);
        }
    }
    env.width = int(w);
    env.height = int(h);
  } catch (const std::bad_alloc&) {
    throw std::runtime_error(path + ": out of memory reading the environment map");
  } catch (const std::exception& e) {
    throw std::runtime_error(one_line(path + ": cannot read the environment map: " + e.what()));
  }
  return env;
}

}  // namespace pt
