// The probability case's check (grader/src/probability_image.h) on
// synthetic maps: a texel's light measured another way passes, a sampler
// without sin theta fails, and so does a missing picture.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "grader/src/image_files.h"
#include "grader/src/probability_image.h"
#include "tests/support.h"

using namespace grader;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kW = 128, kH = 64;

// A sky of the kind sky_sun.exr is: blue, brighter toward the horizon, a
// brown ground, and a small warm sun 35 degrees up.
pt::Color texel(int x, int y) {
  const double theta = kPi * (y + 0.5) / kH, phi = 2 * kPi * (x + 0.5) / kW;
  if (theta > kPi / 2) return pt::Color(0.12f, 0.08f, 0.05f);
  const double up = std::cos(theta);
  pt::Color sky(float(0.3 + 0.5 * (1 - up)), float(0.5 + 0.4 * (1 - up)), 1.0f);
  if (std::fabs(theta - 55 * kPi / 180) < 0.06 && std::fabs(phi - 2.0) < 0.1) sky = pt::Color(2000, 1800, 1400);
  return sky;
}

double luminance(const pt::Color& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }
double mean_rgb(const pt::Color& c) { return (c.x + c.y + c.z) / 3.0; }
double max_rgb(const pt::Color& c) { return std::max({c.x, c.y, c.z}); }

// The picture pathtracer --env-probability writes for texel weights `weight`.
std::string picture(const pt::test::TempDir& dir, const std::string& name,
                    const std::function<double(int, int)>& weight) {
  std::vector<double> p(size_t(kW) * kH);
  double total = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) total += p[size_t(y) * kW + size_t(x)] = weight(x, y);
  std::vector<unsigned char> rgb(p.size() * 3);
  for (size_t i = 0; i < p.size(); ++i) {
    const double q = p[i] / total * double(p.size());
    const double g = q > 0 ? std::clamp((std::log10(q) + 3.0) / 6.0, 0.0, 1.0) : 0.0;
    rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = static_cast<unsigned char>(std::lround(255 * g));
  }
  const std::string path = dir.file(name + ".png");
  write_png_rgb(path, kW, kH, rgb);
  return path;
}

double sin_theta(int y) { return std::sin(kPi * (y + 0.5) / kH); }

}  // namespace

TEST_CASE("Probability image: another brightness measure passes, a sampler without sin theta fails", "[grader]") {
  pt::test::TempDir dir;
  const std::string ref = picture(dir, "reference", [](int x, int y) { return luminance(texel(x, y)) * sin_theta(y); });
  SECTION("the mean of r, g and b") {
    const Check k = check_probability_image(
        picture(dir, "mean", [](int x, int y) { return mean_rgb(texel(x, y)) * sin_theta(y); }), ref, 1.0);
    INFO(k.metric);
    CHECK(k.problems.empty());
    CHECK(k.credit == 1.0);
  }
  SECTION("the largest of r, g and b") {
    const Check k = check_probability_image(
        picture(dir, "max", [](int x, int y) { return max_rgb(texel(x, y)) * sin_theta(y); }), ref, 1.0);
    INFO(k.metric);
    CHECK(k.problems.empty());
  }
  SECTION("the exact solid angle of a row instead of sin theta at its centre") {
    const Check k = check_probability_image(picture(dir, "exact", [](int x, int y) {
                                              return luminance(texel(x, y)) *
                                                     (std::cos(kPi * y / kH) - std::cos(kPi * (y + 1) / kH));
                                            }),
                                            ref, 1.0);
    CHECK(k.problems.empty());
  }
  SECTION("without sin theta") {
    const Check k = check_probability_image(
        picture(dir, "no_sin", [](int x, int y) { return luminance(texel(x, y)); }), ref, 1.0);
    REQUIRE(k.problems.size() == 1);
    CHECK_THAT(k.problems[0], Catch::Contains("sin theta"));
    CHECK(k.credit == 0);
  }
  SECTION("uniform over the map's texels") {
    const Check k = check_probability_image(picture(dir, "uniform", [](int, int) { return 1.0; }), ref, 1.0);
    CHECK(k.credit == 0);
  }
  SECTION("no picture, or one of another size") {
    CHECK(check_probability_image(dir.file("missing.png"), ref, 1.0).credit == 0);
    std::vector<unsigned char> small(3 * 4 * 2, 128);
    write_png_rgb(dir.file("small.png"), 4, 2, small);
    const Check k = check_probability_image(dir.file("small.png"), ref, 1.0);
    CHECK(k.credit == 0);
    REQUIRE(k.problems.size() == 1);
    CHECK_THAT(k.problems[0], Catch::Contains("4 x 2"));
  }
}

TEST_CASE("Probability image: the comparison's figures", "[grader]") {
  pt::ImageBuffer ref(4, 1), cand(4, 1);
  // Greys 51, 102, 130 and 0 (black: not compared); the candidate 21 greys
  // (0.49 decade) up everywhere, and one texel 85 greys (2 decades) more.
  const float r[4] = {51, 102, 130, 0}, c[4] = {72, 123, 130 + 21 + 85, 200};
  for (int i = 0; i < 4; ++i) {
    ref.pixels[size_t(i)] = pt::Color(r[i]);
    cand.pixels[size_t(i)] = pt::Color(c[i]);
  }
  const ProbabilityComparison k = compare_probability_images(cand, ref);
  CHECK(k.compared == 3);
  CHECK(k.shift == Approx(21 * 6.0 / 255));
  CHECK(k.off == 1);
  CHECK(k.worst == Approx(85 * 6.0 / 255));
  CHECK_FALSE(k.passed());
}
