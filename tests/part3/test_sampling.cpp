// Part 3: the direction samplers and light samplers, checked against their
// densities.
//
// Statistics: chi-square goodness of fit, family-wise level alpha = 0.01
// over the K = 10 chi-square tests of this file (Sidak: each test at
// 1 - 0.99^(1/10) = 0.001005), 1,000,000 samples per test, fixed seeds.
// Directions are binned in equal (cos theta, phi) cells about a frame
// (cells of equal solid angle per ring); expected counts are the density
// integrated numerically over each cell; cells expecting fewer than 5
// samples are pooled. The 10 tests: uniform hemisphere (1), cosine
// hemisphere (1), diffuse sample_f in the local frame (1) and turned about
// two normals (2), area light seen from four points (4), ambient light (1).
// The other checks are deterministic (numerical integrals with stated
// tolerances, exact per-sample values).
//
// Deliberate bug (planted in a scratch copy) -> tests here that failed on it:
//   uniform hemisphere drawn with z = sqrt(u1)     -> uniform hemisphere chi-square, ambient
//                                                     chi-square
//   uniform_hemisphere_pdf() returns 1/pi          -> pdfs integrate to 1, ambient (its pdf)
//   cosine sampler with radius u1 (not sqrt(u1))   -> cosine hemisphere chi-square, both
//                                                     sample_f chi-square tests
//   diffuse f = albedo (not divided by pi)         -> sample_f returns f = albedo over pi
//   Frame::from_normal with a wrong sign, n.z < 0  -> the shading frame is orthonormal
//   area light point drawn over +-dim (not +-dim/2)-> area light chi-square, area light pdf
//                                                     integrates to 1, area light samples report
//   area light pdf without the cosine at the light -> area light pdf integrates to 1, area
//                                                     light samples report
//   area light two-sided (|cos| at the light)      -> area light samples report
//   ambient light sampled about +Z instead of +Y   -> ambient chi-square
//   point light radiance divided by d^2 as well    -> point and directional light samples
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <vector>

#include "common/bsdf.h"
#include "common/frame.h"
#include "common/lights.h"
#include "common/rng.h"
#include "common/samplers.h"
#include "tests/statistics/analytic_scenes.h"
#include "tests/statistics/direction_bins.h"
#include "tests/statistics/hypothesis_tests.h"
#include "tests/statistics/special_functions.h"

using namespace pt;
using namespace pt::test;

namespace {

constexpr double kAlpha = 0.01;
constexpr int kChiSquareTests = 10;
constexpr int kSamples = 1000000;
const double kAlphaEach = sidak(kAlpha, kChiSquareTests);

using Density = std::function<double(const Vec3&)>;
using Draw = std::function<Vec3(Rng&)>;

// Bins kSamples directions drawn by `draw` and compares them with `pdf`.
ChiSquareResult fit(const DirectionBins& bins, const Draw& draw, const Density& pdf, int sub, uint64_t seed,
                    bool zero_is_impossible = true, int refine = 1) {
  std::vector<double> observed(size_t(bins.size()), 0.0);
  Rng rng(seed);
  for (int i = 0; i < kSamples; ++i) observed[size_t(bins.cell(draw(rng)))] += 1.0;
  std::vector<double> expected = bins.integrate(pdf, sub, true, refine);
  for (double& e : expected) e *= kSamples;
  return chi_square_test(observed, expected, zero_is_impossible);
}

void check_fit(const ChiSquareResult& r) {
  stats_log(r.describe());
  INFO(r.describe() << "; each test at level " << kAlphaEach << ", critical value "
                    << chi2_upper_quantile(kAlphaEach, r.dof));
  CHECK(r.p_value >= kAlphaEach);
}

// Bins over the whole sphere about the frame's z axis.
DirectionBins sphere_bins(const Frame& f) {
  DirectionBins b;
  b.frame = f;
  b.n_cos = 20;  // 10 rings above the horizon, 10 below
  b.n_phi = 24;
  b.cos_min = -1.0;
  return b;
}

// An orthonormal frame about n built by Gram-Schmidt in double precision,
// independently of Frame::from_normal.
Frame reference_frame(const Vec3& n_) {
  const Vec3d n = normalize(to_d(n_));
  const Vec3d seed = std::fabs(n.x) < 0.6 ? Vec3d(1, 0, 0) : Vec3d(0, 1, 0);
  const Vec3d x = normalize(seed - n * dot(seed, n));
  const Vec3d y = cross(n, x);
  Frame f;
  f.x = Vec3(float(x.x), float(x.y), float(x.z));
  f.y = Vec3(float(y.x), float(y.y), float(y.z));
  f.z = Vec3(float(n.x), float(n.y), float(n.z));
  return f;
}

Frame local_frame() { return reference_frame(Vec3(0, 0, 1)); }

double cosine_density_about(const Vec3& n, const Vec3& w) {
  const double c = dot(to_d(n), normalize(to_d(w)));
  return c > 0 ? c / M_PI : 0.0;
}

// The light of the area-light tests: a 0.8 x 0.5 rectangle tilted 15 degrees
// about z, emitting downward along its normal, and the four points it is
// seen from (straight below, far and oblique, close, near grazing).
Light test_area_light() {
  const float a = float(15.0 * M_PI / 180.0);
  const Vec3 dx = Vec3(std::cos(a), std::sin(a), 0.0f) * 0.8f;
  const Vec3 dy(0.0f, 0.0f, 0.5f);
  return area_light(Vec3(0.3f, 1.2f, -0.2f), dx, dy, normalize(cross(dx, dy)), Color(1.0f, 2.0f, 3.0f));
}
const std::vector<Vec3> kViewPoints = {
    Vec3(0.3f, 0.0f, -0.2f), Vec3(-1.5f, 0.2f, 0.8f), Vec3(0.35f, 1.0f, -0.1f), Vec3(2.0f, 1.0f, 0.3f)};

// A cap about the direction from p to the light's centre that holds every
// direction toward the light, with a margin.
DirectionBins light_cap(const Light& l, const Vec3& p) {
  const Vec3d axis = normalize(to_d(l.position) - to_d(p));
  double cos_min = 1.0;
  for (const Vec3d& q : area_light_corners(l)) cos_min = std::min(cos_min, dot(axis, normalize(q - to_d(p))));
  DirectionBins b;
  b.frame = reference_frame(Vec3(float(axis.x), float(axis.y), float(axis.z)));
  b.n_cos = 12;
  b.n_phi = 32;
  b.cos_min = std::max(-1.0, cos_min - 0.05 * (1.0 - cos_min));
  return b;
}

// The pdf common/lights.h reports for direction w from p: the sample whose
// uniform numbers land on the point of the light that w reaches (0 where w
// misses the light).
double implementation_area_pdf(const Light& l, const Vec3& p, const Vec3& w) {
  double a, b, t;
  if (!area_light_plane_hit(l, to_d(p), normalize(to_d(w)), &a, &b, &t)) return 0.0;
  const double u1 = a + 0.5, u2 = b + 0.5;
  if (!(u1 >= 0 && u1 < 1 && u2 >= 0 && u2 < 1)) return 0.0;
  return sample_light(l, p, float(u1), float(u2)).pdf;
}

}  // namespace

TEST_CASE("the statistics helpers reproduce tabulated quantiles and pool sparse cells", "[part3][sampling][stats]") {
  // Upper quantiles from standard tables.
  CHECK(normal_upper_quantile(0.005) == Approx(2.575829).epsilon(1e-6));
  CHECK(chi2_upper_quantile(0.01, 10) == Approx(23.2093).epsilon(1e-5));
  CHECK(chi2_upper_quantile(0.01, 100) == Approx(135.807).epsilon(1e-5));
  CHECK(chi2_upper_quantile(0.05, 1) == Approx(3.841459).epsilon(1e-6));
  CHECK(student_t_upper_quantile(0.005, 10) == Approx(3.169273).epsilon(1e-6));
  CHECK(student_t_upper_quantile(0.025, 5) == Approx(2.570582).epsilon(1e-6));
  CHECK(student_t_sf(-1.0, 7) == Approx(1.0 - student_t_sf(1.0, 7)).epsilon(1e-12));
  CHECK(sidak(0.01, 10) == Approx(0.00100453).epsilon(1e-5));
  // Two sparse cells (expected 2 and 3) pool into one of expected 5.
  const ChiSquareResult r = chi_square_test({10, 1, 4, 25}, {10, 2, 3, 25});
  CHECK(r.cells == 3);
  CHECK(r.pooled_cells == 2);
  CHECK(r.statistic == Approx(0.0).margin(1e-12));
  // A sample where the density is zero fails the test outright.
  CHECK(chi_square_test({10, 1, 20}, {11, 0, 20}).p_value == 0.0);
}

TEST_CASE("uniform hemisphere sampling fits the density 1 over 2 pi, chi-square", "[part3][sampling][chi2]") {
  const Draw draw = [](Rng& rng) {
    const float u1 = rng.uniform(), u2 = rng.uniform();
    return sample_uniform_hemisphere(u1, u2);
  };
  const Density pdf = [](const Vec3& w) { return w.z >= 0 ? 1.0 / (2.0 * M_PI) : 0.0; };
  check_fit(fit(sphere_bins(local_frame()), draw, pdf, 8, 101));
  // Unit vectors.
  Rng rng(102);
  for (int i = 0; i < 1000; ++i) {
    const Vec3 w = draw(rng);
    REQUIRE(std::fabs(norm(w) - 1.0f) < 1e-5f);
  }
}

TEST_CASE("cosine hemisphere sampling fits the density cos over pi, chi-square", "[part3][sampling][chi2]") {
  const Draw draw = [](Rng& rng) {
    const float u1 = rng.uniform(), u2 = rng.uniform();
    return sample_cosine_hemisphere(u1, u2);
  };
  const Density pdf = [](const Vec3& w) { return cosine_density_about(Vec3(0, 0, 1), w); };
  check_fit(fit(sphere_bins(local_frame()), draw, pdf, 8, 201));
  Rng rng(202);
  for (int i = 0; i < 1000; ++i) {
    const Vec3 w = draw(rng);
    REQUIRE(std::fabs(norm(w) - 1.0f) < 1e-5f);
    REQUIRE(cosine_hemisphere_pdf(w) == Approx(w.z / M_PI).epsilon(1e-5));
  }
}

TEST_CASE("diffuse sample_f returns cosine-weighted directions, chi-square in the local frame",
          "[part3][sampling][chi2][bsdf]") {
  const Material m = diffuse_material(Color(0.2f, 0.5f, 0.8f));
  const Vec3 wo = normalize(Vec3(0.3f, -0.2f, 0.9f));
  const Draw draw = [&](Rng& rng) {
    const float u1 = rng.uniform(), u2 = rng.uniform();
    Vec3 wi;
    float pdf = 0;
    bsdf_sample_f(m, wo, u1, u2, &wi, &pdf);
    return wi;
  };
  const Density pdf = [](const Vec3& w) { return cosine_density_about(Vec3(0, 0, 1), w); };
  check_fit(fit(sphere_bins(local_frame()), draw, pdf, 8, 301));
}

TEST_CASE("diffuse sample_f returns f = albedo over pi and the pdf of its direction", "[part3][sampling][bsdf]") {
  const Material m = diffuse_material(Color(0.2f, 0.5f, 0.8f));
  const Vec3 wo = normalize(Vec3(-0.4f, 0.1f, 0.7f));
  Rng rng(311);
  for (int i = 0; i < 10000; ++i) {
    const float u1 = rng.uniform(), u2 = rng.uniform();
    Vec3 wi;
    float pdf = -1;
    const Color f = bsdf_sample_f(m, wo, u1, u2, &wi, &pdf);
    REQUIRE(std::fabs(norm(wi) - 1.0f) < 1e-5f);
    REQUIRE(wi.z >= 0.0f);
    REQUIRE(pdf == Approx(wi.z / M_PI).epsilon(1e-4).margin(1e-7));
    REQUIRE(bsdf_pdf(m, wo, wi) == Approx(pdf).epsilon(1e-6));
    REQUIRE(f.x == Approx(0.2 / M_PI).epsilon(1e-6));
    REQUIRE(f.y == Approx(0.5 / M_PI).epsilon(1e-6));
    REQUIRE(f.z == Approx(0.8 / M_PI).epsilon(1e-6));
    const Color g = bsdf_f(m, wo, wi);
    REQUIRE(g == f);
  }
  // Emission materials reflect nothing.
  const Material e = emissive_material(Color(3.0f));
  CHECK(bsdf_f(e, wo, Vec3(0, 0, 1)) == Color(0.0f));
  CHECK(emission(e) == Color(3.0f));
}

TEST_CASE("diffuse sample_f turned to world space is cosine-weighted about the normal, chi-square",
          "[part3][sampling][chi2][bsdf][frame]") {
  const Material m = diffuse_material(Color(0.5f));
  // A general normal and one pointing down -Z (the other branch of the
  // frame construction).
  const std::vector<Vec3> normals = {normalize(Vec3(0.3f, -0.5f, 0.81f)), Vec3(0.0f, 0.0f, -1.0f)};
  uint64_t seed = 401;
  for (const Vec3& n : normals) {
    INFO("normal " << n.x << " " << n.y << " " << n.z);
    const Frame frame = Frame::from_normal(n);
    const Draw draw = [&](Rng& rng) {
      const float u1 = rng.uniform(), u2 = rng.uniform();
      Vec3 wi;
      float pdf = 0;
      bsdf_sample_f(m, Vec3(0, 0, 1), u1, u2, &wi, &pdf);
      return frame.to_world(wi);
    };
    const Density pdf = [&](const Vec3& w) { return cosine_density_about(n, w); };
    check_fit(fit(sphere_bins(reference_frame(n)), draw, pdf, 8, seed++));
  }
}

TEST_CASE("the shading frame is orthonormal and right-handed with z the normal", "[part3][sampling][frame]") {
  Rng rng(501);
  std::vector<Vec3> normals = {Vec3(0, 0, 1), Vec3(0, 0, -1), Vec3(1, 0, 0), Vec3(0, -1, 0)};
  for (int i = 0; i < 2000; ++i) {
    const Vec3 v(rng.uniform() * 2 - 1, rng.uniform() * 2 - 1, rng.uniform() * 2 - 1);
    if (norm(v) > 0.1f) normals.push_back(normalize(v));
  }
  for (const Vec3& n : normals) {
    INFO("normal " << n.x << " " << n.y << " " << n.z);
    const Frame f = Frame::from_normal(n);
    REQUIRE(f.z == n);
    REQUIRE(std::fabs(norm(f.x) - 1.0f) < 1e-5f);
    REQUIRE(std::fabs(norm(f.y) - 1.0f) < 1e-5f);
    REQUIRE(std::fabs(dot(f.x, f.y)) < 1e-5f);
    REQUIRE(std::fabs(dot(f.x, f.z)) < 1e-5f);
    REQUIRE(std::fabs(dot(f.y, f.z)) < 1e-5f);
    REQUIRE(norm(cross(f.x, f.y) - f.z) < 1e-5f);
    const Vec3 w = normalize(Vec3(0.2f, -0.7f, 0.4f));
    REQUIRE(norm(f.to_world(f.to_local(w)) - w) < 1e-5f);
    REQUIRE(f.to_local(n).z == Approx(1.0f).epsilon(1e-5));
  }
}

TEST_CASE("sampler pdfs integrate to 1 over the sphere of directions", "[part3][sampling][pdf]") {
  // Numerical integration in (cos theta, phi), 400 x 800 cells: the
  // discretisation error is below 1e-5 for these smooth densities.
  const double uniform = integrate_sphere([](const Vec3& w) { return w.z >= 0 ? double(uniform_hemisphere_pdf()) : 0.0; });
  CHECK(uniform == Approx(1.0).epsilon(1e-4));
  const double cosine = integrate_sphere([](const Vec3& w) { return double(cosine_hemisphere_pdf(w)); });
  CHECK(cosine == Approx(1.0).epsilon(1e-4));
  const Material m = diffuse_material(Color(0.5f));
  const Vec3 wo = normalize(Vec3(0.1f, 0.2f, 0.9f));
  const double bsdf = integrate_sphere([&](const Vec3& w) { return double(bsdf_pdf(m, wo, w)); });
  CHECK(bsdf == Approx(1.0).epsilon(1e-4));
  // The ambient light's pdf over the directions it samples (the +Y
  // hemisphere); every sample reports the same constant.
  Light ambient;
  ambient.type = LightType::Ambient;
  ambient.radiance = Color(1.0f);
  const float ambient_pdf = sample_light(ambient, Vec3(0.0f), 0.3f, 0.6f).pdf;
  const double amb = integrate_sphere([&](const Vec3& w) { return w.y > 0 ? double(ambient_pdf) : 0.0; });
  CHECK(amb == Approx(1.0).epsilon(1e-4));
}

TEST_CASE("area light sampling fits the density of directions toward the rectangle, chi-square from four points",
          "[part3][sampling][chi2][light]") {
  const Light light = test_area_light();
  uint64_t seed = 601;
  for (const Vec3& p : kViewPoints) {
    INFO("seen from " << p.x << " " << p.y << " " << p.z);
    const DirectionBins bins = light_cap(light, p);
    const Draw draw = [&](Rng& rng) {
      const float u1 = rng.uniform(), u2 = rng.uniform();
      return sample_light(light, p, u1, u2).wi;
    };
    const Density pdf = [&](const Vec3& w) { return area_light_density(light, p, w); };
    // The density jumps at the rectangle's outline: 24 x 24 integration
    // points per cell, and 24 x 24 more in each sub-cell the outline
    // crosses, keep the error of the expected counts far below their
    // Poisson noise (checked: over 20 seeds per point the p-values spread
    // evenly over [0, 1]).
    check_fit(fit(bins, draw, pdf, 24, seed++, false, 24));
  }
}

TEST_CASE("area light pdf integrates to 1 over the solid angle of the rectangle", "[part3][sampling][pdf][light]") {
  const Light light = test_area_light();
  for (const Vec3& p : kViewPoints) {
    INFO("seen from " << p.x << " " << p.y << " " << p.z);
    DirectionBins cap = light_cap(light, p);
    // Every direction toward the light lies in the cap (by construction),
    // so the integral over the cap is the integral over the sphere.
    cap.n_cos = 500;
    cap.n_phi = 1000;
    const auto mass = cap.integrate([&](const Vec3& w) { return implementation_area_pdf(light, p, w); }, 1, false);
    double total = 0;
    for (double m : mass) total += m;
    CHECK(total == Approx(1.0).epsilon(2e-3));
    // The reference density gives 1 as well, and the support has the
    // rectangle's solid angle.
    const auto ref = cap.integrate([&](const Vec3& w) { return area_light_density(light, p, w); }, 1, false);
    double ref_total = 0, support = 0;
    for (double m : ref) ref_total += m;
    const auto in =
        cap.integrate([&](const Vec3& w) { return area_light_density(light, p, w) > 0 ? 1.0 : 0.0; }, 1, false);
    for (double m : in) support += m;
    CHECK(ref_total == Approx(1.0).epsilon(2e-3));
    CHECK(support == Approx(polygon_solid_angle(area_light_corners(light), to_d(p))).epsilon(2e-3));
  }
}

TEST_CASE("area light samples report the solid-angle pdf, distance and radiance of their direction",
          "[part3][sampling][light]") {
  const Light light = test_area_light();
  Rng rng(701);
  for (const Vec3& p : kViewPoints) {
    INFO("seen from " << p.x << " " << p.y << " " << p.z);
    for (int i = 0; i < 20000; ++i) {
      const float u1 = rng.uniform(), u2 = rng.uniform();
      const LightSample s = sample_light(light, p, u1, u2);
      REQUIRE(std::fabs(norm(s.wi) - 1.0f) < 1e-5f);
      const double ref = area_light_density(light, p, s.wi);
      REQUIRE(ref > 0);  // the direction reaches the rectangle
      REQUIRE(s.pdf == Approx(ref).epsilon(1e-3));
      // The sampled point is the one for (u1, u2), at the reported distance.
      const Vec3 q = light.position + light.dim_x * (u1 - 0.5f) + light.dim_y * (u2 - 0.5f);
      REQUIRE(s.distance == Approx(norm(q - p)).epsilon(1e-4));
      REQUIRE(norm(p + s.wi * s.distance - q) < 1e-4f);
      REQUIRE(s.radiance == light.radiance);
    }
  }
  // Behind the one-sided light nothing arrives.
  const Vec3 behind = light.position - light.direction * 0.5f;
  for (int i = 0; i < 1000; ++i) {
    const LightSample s = sample_light(light, behind, rng.uniform(), rng.uniform());
    REQUIRE(!(s.pdf > 0 && (s.radiance.x > 0 || s.radiance.y > 0 || s.radiance.z > 0)));
  }
  CHECK_FALSE(light.is_delta());
}

TEST_CASE("ambient light sampling is uniform over the upper hemisphere, chi-square", "[part3][sampling][chi2][light]") {
  Light ambient;
  ambient.type = LightType::Ambient;
  ambient.radiance = Color(0.5f, 1.0f, 2.0f);
  const Vec3 p(0.3f, -0.2f, 0.1f);
  const Draw draw = [&](Rng& rng) {
    const float u1 = rng.uniform(), u2 = rng.uniform();
    return sample_light(ambient, p, u1, u2).wi;
  };
  const Density pdf = [](const Vec3& w) { return w.y >= 0 ? 1.0 / (2.0 * M_PI) : 0.0; };
  check_fit(fit(sphere_bins(reference_frame(Vec3(0, 1, 0))), draw, pdf, 8, 801));
  Rng rng(802);
  for (int i = 0; i < 1000; ++i) {
    const LightSample s = sample_light(ambient, p, rng.uniform(), rng.uniform());
    REQUIRE(s.pdf == Approx(1.0 / (2.0 * M_PI)).epsilon(1e-6));
    REQUIRE(std::isinf(s.distance));
    REQUIRE(s.radiance == ambient.radiance);
    REQUIRE(std::fabs(norm(s.wi) - 1.0f) < 1e-5f);
  }
  CHECK_FALSE(ambient.is_delta());
  // A ray escaping upward sees the ambient radiance, downward nothing.
  CHECK(escaped_radiance({ambient}, normalize(Vec3(0.3f, 0.2f, -0.5f))) == ambient.radiance);
  CHECK(escaped_radiance({ambient}, normalize(Vec3(0.3f, -0.2f, -0.5f))) == Color(0.0f));
}

TEST_CASE("point and directional light samples carry the exact direction, distance and attenuated intensity",
          "[part3][sampling][light]") {
  Light point;
  point.type = LightType::Point;
  point.position = Vec3(0.5f, 2.0f, -1.0f);
  point.radiance = Color(3.0f, 2.0f, 1.0f);
  point.constant_attenuation = 0.5f;
  point.linear_attenuation = 0.25f;
  point.quadratic_attenuation = 0.125f;
  Rng rng(901);
  for (int i = 0; i < 1000; ++i) {
    const Vec3 p(rng.uniform() * 4 - 2, rng.uniform() * 4 - 2, rng.uniform() * 4 - 2);
    const LightSample s = sample_light(point, p, rng.uniform(), rng.uniform());
    const double d = norm(to_d(point.position) - to_d(p));
    const double att = 0.5 + 0.25 * d + 0.125 * d * d;
    REQUIRE(s.pdf == 1.0f);
    REQUIRE(s.distance == Approx(d).epsilon(1e-5));
    REQUIRE(norm(s.wi - (point.position - p) / float(d)) < 1e-5f);
    REQUIRE(s.radiance.x == Approx(3.0 / att).epsilon(1e-5));
    REQUIRE(s.radiance.y == Approx(2.0 / att).epsilon(1e-5));
    REQUIRE(s.radiance.z == Approx(1.0 / att).epsilon(1e-5));
  }
  CHECK(point.is_delta());

  Light sun;
  sun.type = LightType::Directional;
  sun.direction = normalize(Vec3(0.2f, -1.0f, 0.3f));
  sun.radiance = Color(2.0f);
  const LightSample s = sample_light(sun, Vec3(1, 2, 3), 0.4f, 0.7f);
  CHECK(norm(s.wi + sun.direction) < 1e-6f);
  CHECK(std::isinf(s.distance));
  CHECK(s.pdf == 1.0f);
  CHECK(s.radiance == sun.radiance);
  CHECK(sun.is_delta());
}
