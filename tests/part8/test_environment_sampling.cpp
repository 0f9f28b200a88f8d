// Part 8: importance sampling of the environment light, on a map with a
// sky gradient, a small bright sun, a dimmer patch and black rows, checked
// against probabilities and integrals computed here.
//
// Statistics: one family at alpha = 0.01, Sidak-corrected over its K = 17
// tests (each at 1 - 0.99^(1/17) = 5.9e-4), fixed seeds:
//    2  chi-square tests, 1,000,000 samples each: the counts in every
//       texel's four quarters (in phi and theta) against a quarter of the
//       texel's probability (illuminance times sin theta, normalised), and
//       the counts in 20 x 24 cells of equal solid angle (uniform in cos
//       theta and phi, not lined up with the texels) against
//       environment_pdf integrated over each cell;
//    2  z tests: the irradiance of an upward plane estimated with the
//       importance sampler and with the uniform baseline (200,000 samples
//       each) against its quadrature;
//   13  Welch t tests: bunny_ambient.dae lit by the map instead of its sky,
//       --part 7 (uniform sampling) against --part 8, 8x8 blocks of a
//       32x24 image and the image mean (16 seeds each, 4 spp).
// The other checks are exact or deterministic with stated tolerances.
//
// Deliberate bug (planted in a scratch copy) -> tests here that failed on it:
//   texel weight without sin theta                 -> distributions, texel chi-square, pdf
//                                                     integrates (an unbiased but worse sampler:
//                                                     the renders still agree)
//   pdf without the 1 / sin theta of the Jacobian  -> pdf integrates, solid-angle chi-square,
//                                                     irradiance
//   pdf with w h / (2 pi) instead of w h / (2 pi^2)-> pdf integrates, solid-angle chi-square,
//                                                     irradiance
//   the texel's corner instead of a point inside   -> both chi-squares, irradiance
//   conditional CDF over the map's total, not the  -> distributions, both chi-squares
//     row's
//   the Jacobian's sin theta of the texel's centre -> pdf integrates, solid-angle chi-square,
//     instead of wi's                                 irradiance; the failures say so
// (Choosing the row with u2 and the column with u1 changes nothing: the
// two numbers are independent and uniform. Neither do running sums in
// float whose last is not set to exactly 1, nor the first row whose CDF is
// at least u1 instead of above it: the renders and these tests agree.)
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <sstream>
#include <vector>

#include "common/collada.h"
#include "common/lights.h"
#include "common/rng.h"
#include "pathtracer/env_probability.h"
#include "pathtracer/render_job.h"
#include "stages/part8_environment_light/environment_sampling.h"
#include "tests/statistics/analytic_scenes.h"
#include "tests/statistics/hypothesis_tests.h"
#include "tests/statistics/special_functions.h"
#include "tests/support.h"

using namespace pt;
using namespace pt::test;

namespace {

constexpr double kAlpha = 0.01;
constexpr int kTests = 17;
const double kAlphaEach = sidak(kAlpha, kTests);

// 32 x 16: a sky brighter at the top, a sun of 400 in one texel, a
// dimmer 3 x 2 patch, and the two bottom rows black.
std::shared_ptr<EnvironmentMap> test_map() {
  auto m = std::make_shared<EnvironmentMap>();
  m->width = 32;
  m->height = 16;
  m->texels.resize(32 * 16);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 32; ++x) {
      Color c = Color(0.3f, 0.5f, 1.0f) * (0.2f + 0.8f * (1.0f - y / 16.0f));
      if (y >= 14) c = Color(0.0f);
      if (x == 5 && y == 5) c = Color(400.0f, 380.0f, 300.0f);
      if (x >= 20 && x < 23 && y >= 9 && y < 11) c = Color(6.0f, 2.0f, 1.0f);
      m->texels[size_t(y) * 32 + x] = c;
    }
  return m;
}

double luminance(const Color& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

// Each texel's probability: illuminance times sin theta at the row's centre.
std::vector<double> texel_probabilities(const EnvironmentMap& m) {
  std::vector<double> p(m.texels.size());
  double total = 0;
  for (int y = 0; y < m.height; ++y)
    for (int x = 0; x < m.width; ++x) {
      const size_t i = size_t(y) * m.width + x;
      p[i] = luminance(m.texels[i]) * std::sin(M_PI * (y + 0.5) / m.height);
      total += p[i];
    }
  for (double& v : p) v /= total;
  return p;
}

// The course's angles of a direction: theta = acos(y), phi = atan2(-z, x) + pi.
void angles(const Vec3& d, double* theta, double* phi) {
  *theta = std::acos(std::min(1.0, std::max(-1.0, double(d.y))));
  *phi = std::atan2(-double(d.z), double(d.x)) + M_PI;
}
Vec3 direction(double theta, double phi) {
  return Vec3(float(-std::cos(phi) * std::sin(theta)), float(std::cos(theta)), float(std::sin(phi) * std::sin(theta)));
}

// Whether environment_pdf takes the Jacobian's sin theta of the texel's
// centre instead of wi's own: then pdf is the same at two points of one
// texel, where pdf sin theta should be (a hint for the failures below).
bool pdf_uses_texel_centre(const EnvironmentDistribution& d, const EnvironmentMap& map) {
  const double phi = 2 * M_PI * 10.5 / 32;  // texel column 10, row 3 (lit)
  const double t1 = M_PI * 3.2 / 16, t2 = M_PI * 3.8 / 16;
  const double a = environment_pdf(d, map, direction(t1, phi)), b = environment_pdf(d, map, direction(t2, phi));
  return a > 0 && std::fabs(a - b) <= 1e-6 * a && std::fabs(a * std::sin(t1) - b * std::sin(t2)) > 1e-3 * a;
}
const char* const kTexelCentreHint =
    "Hint: your environment_pdf is constant over a texel: its Jacobian w h / (2 pi^2 sin theta) takes sin theta "
    "of the texel's centre. It takes wi's own: sin theta = sqrt(1 - wi.y^2) (a texel's probability is spread "
    "over its solid angle, sin theta d theta d phi, so the density per solid angle goes as 1 / sin theta within "
    "it).";

}  // namespace

TEST_CASE("the distributions: texel probabilities go as illuminance times sin theta, running sums end at 1",
          "[part8][environment]") {
  const auto map = test_map();
  const EnvironmentDistribution d = build_environment_distribution(*map);
  REQUIRE(d.width == 32);
  REQUIRE(d.height == 16);
  REQUIRE(d.pdf.size() == 512u);
  REQUIRE(d.marginal_cdf.size() == 16u);
  REQUIRE(d.conditional_cdf.size() == 512u);
  const std::vector<double> p = texel_probabilities(*map);
  for (size_t i = 0; i < p.size(); ++i) REQUIRE(d.pdf[i] == Approx(p[i]).epsilon(1e-5).margin(1e-12));
  double rows = 0;
  for (int y = 0; y < 16; ++y) {
    double row = 0;
    for (int x = 0; x < 32; ++x) row += p[size_t(y) * 32 + x];
    rows += row;
    INFO("row " << y);
    CHECK(d.marginal_cdf[size_t(y)] == Approx(rows).epsilon(1e-6).margin(1e-12));
    double run = 0;
    for (int x = 0; x < 32; ++x) {
      run += p[size_t(y) * 32 + x];
      if (row > 0) CHECK(d.conditional_cdf[size_t(y) * 32 + x] == Approx(run / row).epsilon(1e-5));
      if (x > 0) CHECK(d.conditional_cdf[size_t(y) * 32 + x] >= d.conditional_cdf[size_t(y) * 32 + x - 1]);
    }
    CHECK(d.conditional_cdf[size_t(y) * 32 + 31] == 1.0f);
  }
  CHECK(d.marginal_cdf.back() == 1.0);
}

TEST_CASE("importance samples fall in each texel with its probability, uniformly within it, chi-square",
          "[part8][environment][chi2]") {
  const auto map = test_map();
  const EnvironmentDistribution d = build_environment_distribution(*map);
  const std::vector<double> p = texel_probabilities(*map);
  const int samples = 1000000;
  // Cells: each texel's quarters (two in phi by two in theta).
  std::vector<double> observed(p.size() * 4, 0.0), expected(p.size() * 4, 0.0);
  for (size_t i = 0; i < p.size(); ++i)
    for (int q = 0; q < 4; ++q) expected[i * 4 + size_t(q)] = p[i] / 4 * samples;
  Rng rng(800);
  for (int i = 0; i < samples; ++i) {
    const LightSample s = sample_environment(d, *map, rng.uniform(), rng.uniform());
    REQUIRE(std::isinf(s.distance));
    double theta, phi;
    angles(s.wi, &theta, &phi);
    const double fx = phi / (2 * M_PI) * 32, fy = theta / M_PI * 16;
    const int x = std::min(31, int(fx)), y = std::min(15, int(fy));
    const int q = (fx - x < 0.5 ? 0 : 1) + (fy - y < 0.5 ? 0 : 2);
    observed[(size_t(y) * 32 + size_t(x)) * 4 + size_t(q)] += 1;
  }
  const ChiSquareResult r = chi_square_test(observed, expected, true);
  stats_log("texel quarters: " + r.describe());
  INFO(r.describe() << "; level " << kAlphaEach);
  CHECK(r.p_value >= kAlphaEach);
}

TEST_CASE("sample_environment reports environment_pdf and the map's radiance of its direction, pdf > 0",
          "[part8][environment][pdf]") {
  const auto map = test_map();
  const EnvironmentDistribution d = build_environment_distribution(*map);
  Rng rng(801);
  for (int i = 0; i < 100000; ++i) {
    const LightSample s = sample_environment(d, *map, rng.uniform(), rng.uniform());
    REQUIRE(std::fabs(norm(s.wi) - 1.0f) < 1e-5f);
    REQUIRE(s.pdf > 0);
    if (environment_pdf(d, *map, s.wi) > 0) {
      REQUIRE(s.pdf == environment_pdf(d, *map, s.wi));
      REQUIRE(s.radiance == map->lookup(s.wi));
    } else {  // rounded onto a black texel: no light
      REQUIRE(s.radiance == Color(0.0f));
    }
  }
}

TEST_CASE("environment_pdf integrates to each texel's probability over its solid angle (the Jacobian)",
          "[part8][environment][pdf]") {
  const auto map = test_map();
  const EnvironmentDistribution d = build_environment_distribution(*map);
  const std::vector<double> p = texel_probabilities(*map);
  double total = 0;
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 32; ++x) {
      // d omega = sin theta d theta d phi, midpoint rule on 8 x 8 points.
      double sum = 0;
      const double dt = M_PI / 16 / 8, dp = 2 * M_PI / 32 / 8;
      for (int a = 0; a < 8; ++a)
        for (int b = 0; b < 8; ++b) {
          const double theta = M_PI * y / 16 + (a + 0.5) * dt, phi = 2 * M_PI * x / 32 + (b + 0.5) * dp;
          sum += double(environment_pdf(d, *map, direction(theta, phi))) * std::sin(theta) * dt * dp;
        }
      INFO("texel " << x << ", " << y);
      CHECK(sum == Approx(p[size_t(y) * 32 + x]).epsilon(2e-3).margin(1e-9));
      total += sum;
    }
  INFO("the density's integral over the sphere is " << total << ". "
       << (pdf_uses_texel_centre(d, *map) ? kTexelCentreHint
                                          : "Hint: environment_pdf is the probability of wi's texel times w h / "
                                            "(2 pi^2 sin theta), sin theta of wi itself."));
  CHECK(total == Approx(1.0).epsilon(1e-4));
  CHECK(environment_pdf(d, *map, Vec3(0, 1, 0)) == 0.0f);  // sin theta = 0
}

TEST_CASE("importance samples fit environment_pdf in cells of equal solid angle, chi-square",
          "[part8][environment][chi2]") {
  const auto map = test_map();
  const EnvironmentDistribution d = build_environment_distribution(*map);
  // 20 rings uniform in cos theta by 24 sectors uniform in phi, which do not
  // line up with the texels. A cell's expected share is the integral of
  // environment_pdf over it, summed over its pieces in each texel; on a
  // piece pdf sin theta is constant (the Jacobian's 1 / sin theta against
  // d omega = sin theta d theta d phi), so one point per piece is exact.
  const int rings = 20, sectors = 24, samples = 1000000;
  std::vector<double> expected(size_t(rings * sectors), 0.0), observed(expected.size(), 0.0);
  auto cuts = [](double lo, double hi, double step) {
    std::vector<double> v = {lo};
    for (double c = std::ceil(lo / step) * step; c < hi; c += step)
      if (c > lo) v.push_back(c);
    v.push_back(hi);
    return v;
  };
  for (int a = 0; a < rings; ++a)
    for (int b = 0; b < sectors; ++b) {
      const double c_hi = 1.0 - 2.0 * a / rings, c_lo = 1.0 - 2.0 * (a + 1) / rings;
      const std::vector<double> ts = cuts(std::acos(c_hi), std::acos(c_lo), M_PI / 16);
      const std::vector<double> ps = cuts(2 * M_PI * b / sectors, 2 * M_PI * (b + 1) / sectors, 2 * M_PI / 32);
      double mass = 0;
      for (size_t i = 0; i + 1 < ts.size(); ++i)
        for (size_t j = 0; j + 1 < ps.size(); ++j) {
          const double t = (ts[i] + ts[i + 1]) / 2, p = (ps[j] + ps[j + 1]) / 2;
          mass += double(environment_pdf(d, *map, direction(t, p))) * std::sin(t) * (ts[i + 1] - ts[i]) *
                  (ps[j + 1] - ps[j]);
        }
      expected[size_t(a * sectors + b)] = mass * samples;
    }
  Rng rng(802);
  for (int i = 0; i < samples; ++i) {
    double theta, phi;
    angles(sample_environment(d, *map, rng.uniform(), rng.uniform()).wi, &theta, &phi);
    const int a = std::min(rings - 1, int((1.0 - std::cos(theta)) / 2 * rings));
    const int b = std::min(sectors - 1, int(phi / (2 * M_PI) * sectors));
    observed[size_t(a * sectors + b)] += 1;
  }
  const ChiSquareResult r = chi_square_test(observed, expected, false);
  stats_log("solid-angle cells: " + r.describe());
  INFO(r.describe() << "; level " << kAlphaEach << ". "
                    << (pdf_uses_texel_centre(d, *map)
                            ? kTexelCentreHint
                            : "Hint: the samples do not follow environment_pdf: if the test of its integral over "
                              "each texel fails too, fix environment_pdf first; else look at how "
                              "sample_environment places a sample within its texel (uniform in phi and theta)."));
  CHECK(r.p_value >= kAlphaEach);
}

TEST_CASE("importance and uniform sampling estimate a plane's irradiance, importance with a tenth the variance",
          "[part8][environment][estimator]") {
  const auto map = test_map();
  // The irradiance at a plane facing +Y: every texel's radiance times the
  // integral of cos theta over its solid angle (cos theta = d.y).
  double E = 0;
  for (int y = 0; y < 8; ++y)  // rows below the horizon send nothing upward
    for (int x = 0; x < 32; ++x) {
      const double t0 = M_PI * y / 16, t1 = M_PI * (y + 1) / 16;
      // integral of cos sin d theta = (sin^2 t1 - sin^2 t0) / 2, times d phi
      E += luminance(map->texels[size_t(y) * 32 + x]) * 0.5 *
           (std::sin(t1) * std::sin(t1) - std::sin(t0) * std::sin(t0)) * (2 * M_PI / 32);
    }
  Light importance;
  importance.type = LightType::Environment;
  importance.environment = map;
  Light uniform = importance;
  importance.sampler = std::make_shared<const ImportanceEnvironmentSampler>(map);
  double variance[2];
  int which = 0;
  uint64_t seed = 810;
  for (const Light* l : {&importance, &uniform}) {
    RunningStats s;
    Rng rng(seed++);
    for (int i = 0; i < 200000; ++i) {
      const LightSample ls = sample_light(*l, Vec3(0.0f), rng.uniform(), rng.uniform());
      s.add(ls.pdf > 0 && ls.wi.y > 0 ? luminance(ls.radiance) * ls.wi.y / ls.pdf : 0.0);
    }
    const ZTest z = z_test(s, E);
    std::ostringstream what;
    what << (l == &importance ? "importance" : "uniform") << ": " << s.mean << " +- " << s.std_error()
         << " against " << E << ", z = " << z.z << ", p = " << z.p_value;
    stats_log(what.str());
    INFO(what.str() << (l == &importance
                            ? ". Hint: each sample adds L cos theta / pdf with the pdf sample_environment reports; "
                              "a biased mean comes from a pdf that does not match where the samples fall (see the "
                              "tests of environment_pdf)"
                            : ""));
    CHECK(z.p_value >= kAlphaEach);
    variance[which++] = s.variance();
  }
  INFO("variance: importance " << variance[0] << ", uniform " << variance[1]);
  CHECK(variance[0] * 10 <= variance[1]);
}

TEST_CASE("a map that sends no light gives empty distributions and samples that carry nothing",
          "[part8][environment]") {
  EnvironmentMap black;
  black.width = 4;
  black.height = 2;
  black.texels.assign(8, Color(0.0f));
  const EnvironmentDistribution d = build_environment_distribution(black);
  CHECK(d.empty());
  const LightSample s = sample_environment(d, black, 0.3f, 0.7f);
  CHECK(s.pdf > 0.0f);  // a light sample's pdf is always positive
  CHECK(s.radiance == Color(0.0f));
  CHECK(environment_pdf(d, black, Vec3(1, 0, 0)) == 0.0f);
}

// --env-probability's picture of where the render samples the map.
TEST_CASE("the probability image: part 8's texel probabilities from the CDFs, uniform ones before part 8",
          "[part8][environment]") {
  const auto map = test_map();
  const std::vector<double> want = texel_probabilities(*map);
  std::string note;
  const std::vector<double> p8 = environment_texel_probabilities(*map, 8, &note);
  CHECK(note.empty());
  REQUIRE(p8.size() == want.size());
  double total = 0;
  for (size_t i = 0; i < p8.size(); ++i) {
    INFO("texel " << i);
    CHECK(p8[i] == Approx(want[i]).epsilon(1e-4).margin(1e-9));
    total += p8[i];
  }
  CHECK(total == Approx(1.0).epsilon(1e-6));
  // Before part 8: each texel's solid angle over 4 pi, the same along a row.
  const std::vector<double> p7 = environment_texel_probabilities(*map, 7, &note);
  REQUIRE(p7.size() == want.size());
  total = 0;
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 32; ++x) {
      const double solid_angle = 2 * M_PI / 32 * (std::cos(M_PI * y / 16) - std::cos(M_PI * (y + 1) / 16));
      CHECK(p7[size_t(y) * 32 + x] == Approx(solid_angle / (4 * M_PI)).epsilon(1e-9));
      total += p7[size_t(y) * 32 + x];
    }
  CHECK(total == Approx(1.0).epsilon(1e-9));
  // A map without light: no distributions, a black image and a warning.
  EnvironmentMap black;
  black.width = 4;
  black.height = 2;
  black.texels.assign(8, Color(0.0f));
  const std::vector<double> none = environment_texel_probabilities(black, 9, &note);
  CHECK(none == std::vector<double>(8, 0.0));
  CHECK(note.find("empty") != std::string::npos);
  // The grey scale: logarithmic, 1000 times below or above the average texel.
  CHECK(probability_grey(0.0, 100) == 0.0);
  CHECK(probability_grey(1.0 / 100, 100) == Approx(0.5));
  CHECK(probability_grey(10.0 / 100, 100) == Approx(4.0 / 6.0));
  CHECK(probability_grey(1e-5 / 100, 100) == 0.0);
  CHECK(probability_grey(1e3 / 100, 100) == 1.0);
}

TEST_CASE("bunny_ambient.dae lit by the map: --part 7 (uniform) and --part 8 agree in mean, by 8x8 blocks",
          "[part8][environment][render]") {
  const int w = 32, h = 24, seeds = 16;
  Scene scene = load_collada(project_scene("bunny_ambient.dae"));
  fit_course_view(scene.camera, w, h);
  scene.lights.clear();
  Light env;
  env.type = LightType::Environment;
  env.environment = test_map();
  scene.lights.push_back(env);
  std::vector<std::vector<double>> seven, eight;
  std::vector<double> seven_mean, eight_mean;
  for (int s = 0; s < seeds; ++s) {
    RenderOptions o;
    o.width = w;
    o.height = h;
    o.samples_per_pixel = 4;
    o.max_depth = 3;
    o.threads = 2;
    o.progress = false;
    o.part = 7;
    o.seed = 8000 + s;
    const RenderResult a = render_scene(scene, o);
    o.part = 8;
    o.seed = 9000 + s;
    const RenderResult b = render_scene(scene, o);
    seven.push_back(block_means(a.image, 8));
    eight.push_back(block_means(b.image, 8));
    seven_mean.push_back(image_mean(a.image));
    eight_mean.push_back(image_mean(b.image));
  }
  const BlockComparison c = compare_blocks(seven, eight, kAlphaEach);
  stats_log("parts 7 and 8: smallest block p " + std::to_string(c.min_p) + "\n" + c.report);
  INFO(c.blocks << " blocks, smallest p = " << c.min_p << ", level " << kAlphaEach << "\n" << c.report);
  CHECK(c.blocks == 12);
  CHECK(c.rejected == 0);
  const WelchTest wt = welch_test(seven_mean, eight_mean);
  INFO("image mean: difference " << wt.difference << " +- " << wt.std_error << ", p = " << wt.p_value);
  CHECK(wt.p_value >= kAlphaEach);
}
