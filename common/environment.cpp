#include "environment.h"

#include <ImfArray.h>
#include <ImfRgbaFile.h>

#include <cmath>
#include <exception>
#include <filesystem>
#include <stdexcept>

#include "samplers.h"

namespace pt {

Color EnvironmentMap::lookup(const Vec3& d) const {
  if (texels.empty()) return Color(0.0f);
  const float theta = std::acos(std::fmax(-1.0f, std::fmin(1.0f, d.y)));
  const float phi = std::atan2(d.x, -d.z);  // [-pi, pi]
  int x = int((phi + kPi) / (2 * kPi) * float(width));
  int y = int(theta / kPi * float(height));
  x = std::min(std::max(x, 0), width - 1);
  y = std::min(std::max(y, 0), height - 1);
  return texels[size_t(y) * size_t(width) + size_t(x)];
}

EnvironmentMap load_environment_map(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) throw std::runtime_error(path + ": no such environment map");
  EnvironmentMap env;
  try {
    Imf::RgbaInputFile file(path.c_str());
    const Imath::Box2i dw = file.dataWindow();
    const long w = long(dw.max.x) - dw.min.x + 1, h = long(dw.max.y) - dw.min.y + 1;
    if (w < 1 || h < 1 || w > 65536 || h > 65536) throw std::runtime_error("bad image size");
    Imf::Array2D<Imf::Rgba> pixels(h, w);
    file.setFrameBuffer(&pixels[0][0] - dw.min.x - long(dw.min.y) * w, 1, size_t(w));
    file.readPixels(dw.min.y, dw.max.y);
    env.width = int(w);
    env.height = int(h);
    env.texels.resize(size_t(w) * size_t(h));
    for (long y = 0; y < h; ++y)
      for (long x = 0; x < w; ++x) {
        const Imf::Rgba& p = pixels[y][x];
        const Color c(float(p.r), float(p.g), float(p.b));
        if (!is_finite(c) || c.x < 0 || c.y < 0 || c.z < 0)
          throw std::runtime_error("texel (" + std::to_string(x) + ", " + std::to_string(y) +
                                   ") is negative or not finite");
        env.texels[size_t(y * w + x)] = c;
      }
  } catch (const std::exception& e) {
    throw std::runtime_error(path + ": cannot read the environment map: " + e.what());
  }
  return env;
}

}  // namespace pt
