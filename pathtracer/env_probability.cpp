#include "pathtracer/env_probability.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "common/image_io.h"
#include "common/math_constants.h"
#include "stages/part8_environment_light/environment_sampling.h"

namespace pt {

std::vector<double> environment_texel_probabilities(const EnvironmentMap& map, int part, std::string* note) {
  const int w = map.width, h = map.height;
  const size_t n = size_t(w) * size_t(h);
  std::vector<double> p(n, 0.0);
  if (part < 8) {
    // Uniform over the sphere: a texel's solid angle, (2 pi / w)(cos theta0
    // - cos theta1), over 4 pi.
    for (int y = 0; y < h; ++y) {
      const double c0 = std::cos(kPiDouble * y / h), c1 = std::cos(kPiDouble * (y + 1) / h);
      std::fill(p.begin() + ptrdiff_t(size_t(y) * size_t(w)), p.begin() + ptrdiff_t(size_t(y + 1) * size_t(w)),
                (c0 - c1) / (2.0 * w));
    }
    return p;
  }
  const EnvironmentDistribution d = build_environment_distribution(map);
  if (d.empty()) {
    *note = "--env-probability: part 8's distributions are empty (a map without light, or "
            "build_environment_distribution not written): the image is black";
    return p;
  }
  if (d.width != w || d.height != h || d.marginal_cdf.size() != size_t(h) || d.conditional_cdf.size() != n)
    throw std::runtime_error("--env-probability: part 8's distributions (" + std::to_string(d.width) + " x " +
                             std::to_string(d.height) + ", " + std::to_string(d.marginal_cdf.size()) + " rows, " +
                             std::to_string(d.conditional_cdf.size()) + " texels) do not fit the " +
                             std::to_string(w) + " x " + std::to_string(h) + " map");
  // What sample_environment inverts: a row by the marginal CDF, then a
  // column by the row's conditional CDF. A CDF that falls gives 0, not a
  // negative probability.
  for (int y = 0; y < h; ++y) {
    const double row = d.marginal_cdf[size_t(y)] - (y > 0 ? d.marginal_cdf[size_t(y - 1)] : 0.0);
    const float* c = d.conditional_cdf.data() + size_t(y) * size_t(w);
    for (int x = 0; x < w; ++x) {
      const double column = double(c[x]) - (x > 0 ? double(c[x - 1]) : 0.0);
      p[size_t(y) * size_t(w) + size_t(x)] = std::max(0.0, row) * std::max(0.0, column);
    }
  }
  return p;
}

double probability_grey(double p, size_t n) {
  if (!(p > 0) || n == 0) return 0.0;
  return std::clamp((std::log10(p * double(n)) + 3.0) / 6.0, 0.0, 1.0);
}

std::vector<uint8_t> encode_environment_probability_png(const EnvironmentMap& map, int part, std::string* note) {
  const std::vector<double> p = environment_texel_probabilities(map, part, note);
  std::vector<uint8_t> rgb(p.size() * 3);
  for (size_t i = 0; i < p.size(); ++i) {
    const auto g = uint8_t(std::lround(255.0 * probability_grey(p[i], p.size())));
    rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = g;
  }
  return encode_png_rgb(rgb, map.width, map.height);
}

}  // namespace pt
