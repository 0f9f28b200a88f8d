#include "grader/src/pictures.h"

#include <algorithm>
#include <cmath>

#include "grader/src/image_files.h"
#include "common/image_io.h"

namespace grader {

Picture radiance_picture(const ImageBuffer& img) { return Picture{img.width, img.height, pt::to_png_bytes(img)}; }

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
  write_png_rgb(path, picture.width, picture.height, picture.rgb);
}

}  // namespace grader
