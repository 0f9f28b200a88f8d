// Part 5: adaptive sampling.
//
// Statistical test: one block z test (alpha = 0.01, Sidak over the blocks),
// batch means over 8 seeds, fixed seeds: it passes or fails the same way on
// every run. Bugs each test catches (checked by planting them):
//   stopping rule on synthetic streams  <- sigma^2 used instead of sigma;
//                                          checking before a batch is full;
//                                          mean instead of 1.96 sigma / sqrt(n)
//   same samples as raytrace_pixel      <- different random numbers per sample
//   adaptive mean = non-adaptive mean   <- returning the sum, or dividing by
//                                          the maximum instead of n
//   rate lower on walls than on edges   <- sample counts not recorded
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "stages/part5_adaptive_sampling/adaptive_sampling.h"
#include "common/collada.h"
#include "pathtracer/render_job.h"
#include "tests/support.h"

using namespace pt;

TEST_CASE("stopping rule: 1.96 sigma / sqrt(n) <= T mu", "[part5][adaptive]") {
  // Constant samples: zero variance, converged as soon as it is checked.
  CHECK(pixel_converged(32 * 0.5, 32 * 0.25, 32, 0.05));
  // Black pixel: mu = 0, sigma = 0: converged (0 <= 0).
  CHECK(pixel_converged(0, 0, 32, 0.05));
  // Alternating 0 / 1: mu = 0.5, sigma ~ 0.5: needs 1.96 * 0.5 / sqrt(n) <= 0.025, n >= 1537.
  const auto alternating = [](int n) {
    const double ones = n / 2;
    return pixel_converged(ones, ones, n, 0.05);
  };
  CHECK_FALSE(alternating(1024));
  CHECK_FALSE(alternating(1536));
  CHECK(alternating(1600));
  // Not decidable from one sample.
  CHECK_FALSE(pixel_converged(1, 1, 1, 0.05));
}

namespace {
Camera small_camera() {
  Camera cam;
  cam.width = 4;
  cam.height = 4;
  return cam;
}
}  // namespace

TEST_CASE("adaptive pixel: a constant stream stops at the first batch, a noisy one uses every sample",
          "[part5][adaptive]") {
  const Camera cam = small_camera();
  int taken = 0;
  const RadianceFn constant = [](const Ray&, Rng&) { return Color(0.3f); };
  AdaptiveOptions o;
  o.batch = 16;
  o.tolerance = 0.05;
  const Color c = raytrace_pixel_adaptive(cam, 1, 2, 1024, 7, constant, o, &taken);
  INFO("Hint: the stopping rule is checked after each full batch of opts.batch samples (n % batch == 0), as in "
       "the course, and never after the last sample: a constant stream stops after its first batch (16 here), a "
       "noisy one takes every sample (1024).");
  CHECK(taken == 16);
  CHECK(c.x == Approx(0.3f));

  const RadianceFn noisy = [](const Ray&, Rng& rng) { return Color(rng.uniform() < 0.5f ? 0.0f : 1.0f); };
  raytrace_pixel_adaptive(cam, 1, 2, 1024, 7, noisy, o, &taken);
  CHECK(taken == 1024);
}

TEST_CASE("adaptive pixel draws the same samples as raytrace_pixel", "[part5][adaptive]") {
  // When it never stops early it must return exactly raytrace_pixel's value.
  const Camera cam = small_camera();
  const RadianceFn noisy = [](const Ray& r, Rng& rng) { return Color(rng.uniform() < 0.5f ? 0.0f : r.d.x + 2); };
  AdaptiveOptions o;
  o.batch = 8;
  int taken = 0;
  const Color a = raytrace_pixel_adaptive(cam, 3, 1, 64, 11, noisy, o, &taken);
  const Color b = raytrace_pixel(cam, 3, 1, 64, 11, noisy);
  REQUIRE(taken == 64);
  CHECK(a == b);
}

namespace {

// The project's Cornell box with the bunny, at a low resolution showing
// the whole 800x600 course frame.
Scene load_box(int w, int h) {
  Scene s = load_collada(test::project_scene("CBbunny.dae"));
  s.camera.screen_dist *= double(w) / 800.0;
  s.camera.set_resolution(w, h);
  return s;
}

RenderOptions gi_options(int w, int h, int spp, uint64_t seed, int part) {
  RenderOptions o;
  o.part = part;
  o.width = w;
  o.height = h;
  o.samples_per_pixel = spp;
  o.light_samples = 1;
  o.max_depth = 2;
  o.threads = 2;
  o.seed = seed;
  o.progress = false;
  return o;
}

}  // namespace

TEST_CASE("an adaptive render agrees in mean with the non-adaptive one, block by block", "[part5][adaptive]") {
  // 32x24 image, 4x4 blocks of 8x6 pixels; 8 seeds each; two-sample z test
  // per block and channel on the batch means, Sidak-corrected alpha = 0.01.
  const int w = 32, h = 24, seeds = 8, bx = 4, by = 4;
  const Scene s = load_box(w, h);
  std::vector<std::vector<double>> fixed(bx * by * 3), adaptive(bx * by * 3);
  for (int k = 0; k < seeds; ++k) {
    for (int mode = 0; mode < 2; ++mode) {
      RenderOptions o = gi_options(w, h, mode == 0 ? 32 : 128, 100 + uint64_t(k), mode == 0 ? 4 : 5);
      o.adaptive_batch = 16;
      o.adaptive_tolerance = 0.05;
      const RenderResult r = render_scene(s, o);
      std::vector<double> block(bx * by * 3, 0.0);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const int b = (y / (h / by)) * bx + x / (w / bx);
          const Color& c = r.image.at(x, y);
          for (int ch = 0; ch < 3; ++ch) block[size_t(b * 3 + ch)] += c[ch] / double((w / bx) * (h / by));
        }
      for (size_t i = 0; i < block.size(); ++i) (mode == 0 ? fixed : adaptive)[i].push_back(block[i]);
    }
  }
  const int tests = bx * by * 3;
  const double alpha = 1 - std::pow(1 - 0.01, 1.0 / tests);
  // Two-sided normal quantile for alpha (bisection on erfc).
  double lo = 0, hi = 10;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    (std::erfc(mid / std::sqrt(2.0)) > alpha ? lo : hi) = mid;
  }
  const double z_crit = lo;
  const auto mean_var = [](const std::vector<double>& v, double* m, double* var) {
    *m = 0;
    for (double x : v) *m += x;
    *m /= double(v.size());
    *var = 0;
    for (double x : v) *var += (x - *m) * (x - *m);
    *var /= double(v.size() - 1);
  };
  for (int i = 0; i < tests; ++i) {
    double ma, va, mb, vb;
    mean_var(fixed[size_t(i)], &ma, &va);
    mean_var(adaptive[size_t(i)], &mb, &vb);
    const double se = std::sqrt(va / seeds + vb / seeds);
    INFO("block " << i / 3 << " channel " << i % 3 << ": fixed " << ma << " adaptive " << mb << " se " << se);
    if (se > 0)
      CHECK(std::abs(ma - mb) / se < z_crit);
    else
      CHECK(ma == mb);
  }
}

TEST_CASE("the sample rate is lower on the back wall than along the bunny's shadow edges", "[part5][adaptive]") {
  // -s 2048 -a 64 0.05 at 40x30. The back wall converges early; the floor
  // around the bunny's base, in its soft shadow, does not. PT_DUMP_RATE=1
  // prints the rate map (0-9) to see the regions.
  const int w = 40, h = 30;
  const Scene s = load_box(w, h);
  RenderOptions o = gi_options(w, h, 2048, 5, 5);
  o.adaptive_batch = 64;
  o.adaptive_tolerance = 0.05;
  o.max_depth = 1;  // direct light: soft shadows under the area light
  const RenderResult r = render_scene(s, o);
  const auto mean_rate = [&](int x0, int y0, int x1, int y1) {
    double sum = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) sum += r.image.samples[r.image.index(x, y)] / 2048.0;
    return sum / ((x1 - x0) * (y1 - y0));
  };
  if (std::getenv("PT_DUMP_RATE"))
    for (int y = h - 1; y >= 0; --y) {
      for (int x = 0; x < w; ++x) std::printf("%d", std::min(9, int(r.image.samples[r.image.index(x, y)] * 10 / 2049)));
      std::printf("\n");
    }
  // The box fills the middle of the frame (x 8..31, y 6..23), the bunny
  // x 16..23, y 7..14.
  const double wall = mean_rate(10, 15, 30, 19);   // back wall, above the bunny
  const double shadows = mean_rate(14, 7, 24, 9);  // floor along the bunny's base
  INFO("wall rate " << wall << ", shadow rate " << shadows);
  CHECK(wall < 0.5 * shadows);
  for (uint32_t n : r.image.samples) {
    CHECK(n >= 64u);
    CHECK(n <= 2048u);
  }
}
