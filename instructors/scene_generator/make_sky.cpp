// make_sky: writes the project's environment maps (latitude-longitude
// OpenEXR images, oriented as common/environment.h states).
//   make_sky OUT.exr          scenes/sky_bands.exr: bright and dark bands of
//                             latitude (every 5.625 degrees). Any error in
//                             the elevation of a direction looked up in it (a
//                             camera ray that is not unit length, say) moves
//                             the bands, which a smooth sky would hide.
//   make_sky --sun OUT.exr    scenes/sky_sun.exr: a blue sky brighter toward
//                             the horizon, a dim brown ground and a small
//                             sun, 1.5 degrees across the disk's radius, of
//                             radiance 2000 (about half the light an upward
//                             plane gets): a map that uniform sampling of the
//                             sphere renders with bright speckles and
//                             importance sampling (part 8) cleanly.
//   make_sky --wide-sun OUT.exr
//                             scenes/sky_wide_sun.exr: the same sky with a
//                             sun 10 degrees across the disk's radius, of
//                             radiance 50 (again about half the light): a
//                             uniform sample of the sphere finds it 1 time
//                             in 130, often enough that four renders of a
//                             few dozen samples measure the speckles'
//                             variance (the grader's noise check); the
//                             small sun's speckles are too rare for that.
#include <ImfRgbaFile.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <vector>

namespace {

struct Rgb {
  float r, g, b;
};

// The course's layout: row y from the top at theta = pi (y + 0.5) / h,
// column x at phi = 2 pi (x + 0.5) / w; direction
// (-cos phi sin theta, cos theta, sin phi sin theta).
Rgb sun_sky(int x, int y, int w, int h, double sun_radius_degrees, Rgb sun) {
  const double kPi = 3.14159265358979323846;
  const double theta = kPi * (y + 0.5) / h, phi = 2 * kPi * (x + 0.5) / w;
  const double dx = -std::cos(phi) * std::sin(theta), dy = std::cos(theta), dz = std::sin(phi) * std::sin(theta);
  // The sun: 35 degrees up, toward the front left of a scene seen from +Z.
  const double se = 35 * kPi / 180, sa = 0.8;
  const double sx = -std::sin(sa) * std::cos(se), sy = std::sin(se), sz = std::cos(sa) * std::cos(se);
  if (dx * sx + dy * sy + dz * sz > std::cos(sun_radius_degrees * kPi / 180)) return sun;
  if (dy < 0) return {0.12f, 0.1f, 0.08f};  // the ground
  const float t = float(std::pow(1.0 - dy, 3));  // 0 at the zenith, 1 at the horizon
  return {0.25f + 0.75f * t, 0.45f + 0.55f * t, 1.0f};
}

int write(const char* path, int width, int height, const std::vector<Imf::Rgba>& pixels) {
  try {
    Imf::RgbaOutputFile file(path, width, height, Imf::WRITE_RGBA);
    file.setFrameBuffer(pixels.data(), 1, size_t(width));
    file.writePixels(height);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "make_sky: %s: %s\n", path, e.what());
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const bool sun = argc == 3 && std::strcmp(argv[1], "--sun") == 0;
  const bool wide_sun = argc == 3 && std::strcmp(argv[1], "--wide-sun") == 0;
  if (!(argc == 2 || sun || wide_sun)) {
    std::fprintf(stderr, "usage: make_sky OUT.exr | make_sky --sun OUT.exr | make_sky --wide-sun OUT.exr\n");
    return 2;
  }
  if (sun || wide_sun) {
    const double radius = sun ? 1.5 : 10.0;
    const Rgb disk = sun ? Rgb{2000.0f, 1900.0f, 1700.0f} : Rgb{50.0f, 47.5f, 42.5f};
    const int width = 512, height = 256;
    std::vector<Imf::Rgba> pixels(size_t(width) * height);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const Rgb c = sun_sky(x, y, width, height, radius, disk);
        pixels[size_t(y) * width + x] = Imf::Rgba(c.r, c.g, c.b, 1.0f);
      }
    return write(argv[2], width, height, pixels);
  }
  const int width = 64, height = 256, band_rows = 8;
  std::vector<Imf::Rgba> pixels(size_t(width) * height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const float v = (y / band_rows) % 2 ? 1.0f : 0.1f;
      pixels[size_t(y) * width + x] = Imf::Rgba(v, v, v, 1.0f);
    }
  return write(argv[1], width, height, pixels);
}
