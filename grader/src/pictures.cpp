#include "pictures.h"

#include <lodepng.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "image_io.h"

namespace grader {

Picture radiance_picture(const Image& img) {
  Picture p{img.width, img.height, std::vector<unsigned char>(size_t(img.width) * img.height * 3)};
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      for (int c = 0; c < 3; ++c)
        p.rgb[(size_t(y) * img.width + x) * 3 + c] = pt::radiance_to_byte(img.at(x, y, img.channels == 3 ? c : 0));
  return p;
}

Picture error_picture(const std::vector<float>& z, int width, int height, double threshold) {
  Picture p{width, height, std::vector<unsigned char>(size_t(width) * height * 3)};
  for (size_t i = 0; i < z.size() && i < size_t(width) * height; ++i) {
    unsigned char* px = &p.rgb[i * 3];
    const double t = threshold > 0 ? z[i] / threshold : 0;
    if (t > 1) {
      px[0] = 255, px[1] = 40, px[2] = 40;
    } else {
      const double u = std::sqrt(std::max(0.0, t));
      px[0] = (unsigned char)(255 * u * u);
      px[1] = (unsigned char)(255 * u * u);
      px[2] = (unsigned char)(255 * u);
    }
  }
  return p;
}

Picture side_by_side(const std::vector<Picture>& pictures, int gap) {
  Picture out;
  for (const Picture& p : pictures) {
    out.width += p.width + (out.width > 0 ? gap : 0);
    out.height = std::max(out.height, p.height);
  }
  out.rgb.assign(size_t(out.width) * out.height * 3, 255);
  int x0 = 0;
  for (const Picture& p : pictures) {
    for (int y = 0; y < p.height; ++y)
      std::copy_n(&p.rgb[size_t(y) * p.width * 3], size_t(p.width) * 3, &out.rgb[(size_t(y) * out.width + x0) * 3]);
    x0 += p.width + gap;
  }
  return out;
}

void save_picture(const std::string& path, const Picture& picture) {
  std::vector<unsigned char> png;
  const unsigned err = lodepng::encode(png, picture.rgb, unsigned(picture.width), unsigned(picture.height), LCT_RGB, 8);
  if (err) throw std::runtime_error(path + ": " + lodepng_error_text(err));
  pt::write_file_atomically(path, std::vector<uint8_t>(png.begin(), png.end()));
}

}  // namespace grader
