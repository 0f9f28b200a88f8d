// Part 8: importance sampling of the environment light: directions drawn
// in proportion to the light the map sends, per unit solid angle.
//
// The map is a latitude-longitude image (common/environment.h): texel
// (x, y), x from the left and y from the top, covers the angles
// phi in [2 pi x / w, 2 pi (x + 1) / w) and theta in [pi y / h, pi (y + 1) / h).
// A texel's solid angle is about sin(theta) (2 pi / w) (pi / h): rows near
// the poles cover less of the sphere, so a texel's weight is its
// illuminance times sin(theta) at its centre row.
#pragma once
#include <memory>
#include <vector>

#include "common/environment.h"
#include "common/lights.h"

namespace pt {

// The distributions of the map's texels (the course's pdf_envmap,
// marginal_y and conds_y), row by row from the top.
struct EnvironmentDistribution {
  int width = 0, height = 0;
  std::vector<float> pdf;              // width * height: each texel's probability (they sum to 1)
  std::vector<double> marginal_cdf;    // height: probability that the row is <= y
  std::vector<float> conditional_cdf;  // width * height: within row y, probability that the column is <= x
  bool empty() const { return pdf.empty(); }
};

// The distributions of `map`: texel (x, y) weighs illum(texel) *
// sin(pi (y + 0.5) / h); pdf is the weights divided by their sum,
// marginal_cdf the running sum of the rows' probabilities (the last is 1),
// conditional_cdf each row's running sum divided by the row's total (the
// last of each row is 1). A map that sends no light at all gives empty
// distributions.
EnvironmentDistribution build_environment_distribution(const EnvironmentMap& map);

// A direction toward the map drawn from the distributions with two uniform
// numbers in [0, 1): the row by inverting marginal_cdf with u1, the column
// by inverting the row's conditional_cdf with u2, and the point within the
// texel from what is left of each number (u1 and u2 rescaled to [0, 1)
// inside the interval of the chosen row and column), so that directions are
// uniform in (phi, theta) within a texel. Returns the direction (world,
// unit), its solid-angle pdf environment_pdf(wi) and the map's radiance
// lookup(wi), at infinite distance. As every light sample's (common/
// lights.h), the pdf is positive: a sample that brings no light (empty
// distributions, or environment_pdf(wi) = 0) has radiance 0 and pdf 1.
LightSample sample_environment(const EnvironmentDistribution& d, const EnvironmentMap& map, float u1, float u2);

// The solid-angle density of sample_environment's directions at wi (unit):
// the probability of wi's texel (map.texel_of) times w h / (2 pi^2
// sin theta), the Jacobian from the image's (x / w, y / h) square to solid
// angle. 0 at the poles (sin theta = 0) and for empty distributions.
float environment_pdf(const EnvironmentDistribution& d, const EnvironmentMap& map, const Vec3& wi);

// Given: the environment light's sampler from part 8 on, built once per
// map (common/lights.h's EnvironmentSampler).
class ImportanceEnvironmentSampler : public EnvironmentSampler {
 public:
  explicit ImportanceEnvironmentSampler(std::shared_ptr<const EnvironmentMap> map);
  LightSample sample(float u1, float u2) const override;
  float pdf(const Vec3& wi) const override;
  const EnvironmentDistribution& distribution() const { return dist_; }

 private:
  std::shared_ptr<const EnvironmentMap> map_;
  EnvironmentDistribution dist_;
};

}  // namespace pt
