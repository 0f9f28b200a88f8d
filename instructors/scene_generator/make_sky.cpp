// make_sky: writes scenes/sky_bands.exr, a latitude-longitude environment
// map of bright and dark bands of latitude (every 5.625 degrees). Any error
// in the elevation of a direction looked up in it (a camera ray that is not
// unit length, say) moves the bands, which a smooth sky would hide.
//   make_sky OUT.exr
#include <ImfRgbaFile.h>

#include <cstdio>
#include <exception>
#include <vector>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_sky OUT.exr\n");
    return 2;
  }
  const int width = 64, height = 256, band_rows = 8;
  std::vector<Imf::Rgba> pixels(size_t(width) * height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const float v = (y / band_rows) % 2 ? 1.0f : 0.1f;
      pixels[size_t(y) * width + x] = Imf::Rgba(v, v, v, 1.0f);
    }
  try {
    Imf::RgbaOutputFile file(argv[1], width, height, Imf::WRITE_RGBA);
    file.setFrameBuffer(pixels.data(), 1, width);
    file.writePixels(height);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "make_sky: %s: %s\n", argv[1], e.what());
    return 1;
  }
  return 0;
}
