#include "stages/part8_environment_light/environment_sampling.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "common/math_constants.h"
#include "common/todo.h"

namespace pt {

EnvironmentDistribution build_environment_distribution(const EnvironmentMap& map) {
  // BEGIN SOLUTION
  // STUB: PT_TODO(8, "no distributions");
  // STUB: unused(map);
  // STUB: return EnvironmentDistribution{};
  EnvironmentDistribution d;
  const int w = map.width, h = map.height;
  if (w < 1 || h < 1 || map.texels.size() != size_t(w) * size_t(h)) return d;
  // Weights and sums in double: a large map's running sums need the digits.
  std::vector<double> weight(size_t(w) * size_t(h));
  std::vector<double> row_sum(size_t(h), 0.0);
  double total = 0;
  for (int y = 0; y < h; ++y) {
    const double s = std::sin(kPiDouble * (y + 0.5) / h);
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      weight[i] = double(illum(map.texels[i])) * s;
      row_sum[size_t(y)] += weight[i];
    }
    total += row_sum[size_t(y)];
  }
  if (!(total > 0)) return d;
  d.width = w;
  d.height = h;
  d.pdf.resize(weight.size());
  d.conditional_cdf.resize(weight.size());
  d.marginal_cdf.resize(size_t(h));
  double rows = 0;
  for (int y = 0; y < h; ++y) {
    rows += row_sum[size_t(y)];
    d.marginal_cdf[size_t(y)] = rows / total;
    double run = 0;
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      d.pdf[i] = float(weight[i] / total);
      run += weight[i];
      // A row without light is never chosen; it gets a uniform CDF.
      d.conditional_cdf[i] = float(row_sum[size_t(y)] > 0 ? run / row_sum[size_t(y)] : double(x + 1) / w);
    }
    d.conditional_cdf[size_t(y) * size_t(w) + size_t(w - 1)] = 1.0f;
  }
  d.marginal_cdf[size_t(h - 1)] = 1.0;
  return d;
  // END SOLUTION
}

LightSample sample_environment(const EnvironmentDistribution& d, const EnvironmentMap& map, float u1, float u2) {
  // BEGIN SOLUTION
  // STUB: PT_TODO(8, "the map sampled uniformly over the sphere");
  // STUB: unused(d);
  // STUB: return sample_environment_uniform(&map, u1, u2);
  LightSample s;  // no light: radiance 0, pdf 1
  if (d.empty()) return s;
  const int w = d.width, h = d.height;
  // The first row whose running sum exceeds u1, and where u1 falls in it.
  const auto& mc = d.marginal_cdf;
  const int y = int(std::min<ptrdiff_t>(std::upper_bound(mc.begin(), mc.end(), double(u1)) - mc.begin(), h - 1));
  const double y_lo = y > 0 ? mc[size_t(y - 1)] : 0.0, y_hi = mc[size_t(y)];
  const double fy = y_hi > y_lo ? std::min((u1 - y_lo) / (y_hi - y_lo), 1.0) : 0.5;
  // The same within the row for the column.
  const float* row = d.conditional_cdf.data() + size_t(y) * size_t(w);
  const int x = int(std::min<ptrdiff_t>(std::upper_bound(row, row + w, u2) - row, w - 1));
  const double x_lo = x > 0 ? row[x - 1] : 0.0, x_hi = row[x];
  const double fx = x_hi > x_lo ? std::min((u2 - x_lo) / (x_hi - x_lo), 1.0) : 0.5;
  const double theta = kPiDouble * (y + fy) / h, phi = 2.0 * kPiDouble * (x + fx) / w;
  s.wi = angles_to_direction(float(theta), float(phi));
  s.distance = kInfinity;
  s.pdf = environment_pdf(d, map, s.wi);
  s.radiance = map.lookup(s.wi);
  // A direction of density 0 (rounded onto a black texel's edge, or a
  // pole) brings no light; the pdf of a light sample stays positive.
  if (!(s.pdf > 0)) {
    s.pdf = 1.0f;
    s.radiance = Color(0.0f);
  }
  return s;
  // END SOLUTION
}

float environment_pdf(const EnvironmentDistribution& d, const EnvironmentMap& map, const Vec3& wi) {
  // BEGIN SOLUTION
  // STUB: PT_TODO(8, "the uniform density 1 / (4 pi)");
  // STUB: unused(d, map, wi);
  // STUB: return 1.0f / (4.0f * kPi);
  if (d.empty()) return 0.0f;
  const float sin_theta = std::sqrt(std::fmax(0.0f, 1.0f - wi.y * wi.y));
  if (!(sin_theta > 0)) return 0.0f;
  int x = 0, y = 0;
  map.texel_of(wi, &x, &y);
  const float p = d.pdf[size_t(y) * size_t(d.width) + size_t(x)];
  return p * float(d.width) * float(d.height) / (2.0f * kPi * kPi * sin_theta);
  // END SOLUTION
}

ImportanceEnvironmentSampler::ImportanceEnvironmentSampler(std::shared_ptr<const EnvironmentMap> map)
    : map_(std::move(map)), dist_(build_environment_distribution(*map_)) {}

LightSample ImportanceEnvironmentSampler::sample(float u1, float u2) const {
  return sample_environment(dist_, *map_, u1, u2);
}

float ImportanceEnvironmentSampler::pdf(const Vec3& wi) const { return environment_pdf(dist_, *map_, wi); }

}  // namespace pt
