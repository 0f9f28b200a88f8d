// Part 4: global illumination (paths of -m bounces, Russian roulette, -o),
// tested through whole renders made in-process.
//
// Statistics: one family per file at alpha = 0.01, Sidak-corrected over its
// K = 114 tests (each at 1 - 0.99^(1/114) = 8.82e-5), fixed seeds, batch
// means over independent renders (one batch per seed):
//    2  Welch t tests: sphere_ambient.dae, image mean with -m 1 against
//       -m 5, light sampling and -H (16 seeds each, 32x24, 4 spp);
//   49  Welch t tests: CBspheres_lambertian.dae at -m 5, Russian roulette
//       on against off, 8x8 blocks of a 64x48 image and the image mean
//       (16 seeds each, 4 spp);
//   49  Welch t tests: the sum of the -o 0 images for m = 0..5 against the
//       -o 1 image at -m 5, same blocks and image mean (16 seeds each);
//   12  one-sided t tests: a closed box of albedo 0.5, the image mean at
//       -m m against -m m-1 for m = 1..6 (it must grow) and each bounce's
//       share against the energy bound rho^(m-1) rho E_max / pi (it must
//       not exceed it); 8 seeds, the same seed for every m (common random
//       numbers), 32x24, 4 spp;
//    2  two-sided one-sample t tests: the inside of a closed diffuse sphere
//       (albedo 0.5), the --indirect-only image mean against the
//       integrating sphere's value at -m 2 and -m 5 (16 seeds each, 32x24,
//       8 spp).
// The remaining checks are deterministic.
//
// Deliberate bug (planted in a scratch copy) -> tests here that failed on it:
//   no division by the Russian-roulette probability -> Russian roulette on and off agree
//   -o 0 accumulating anyway                         -> the -o 0 images sum to the -o 1 image
//   bounce ray without min_t epsilon                 -> convex sphere, -m 1 against -m 5
//   escaped bounce ray adds the sky again            -> convex sphere, -m 1 against -m 5
//   missing cosine in the bounce weight              -> closed box (energy bound)
//   2 % of the light lost at every bounce            -> the integrating sphere (only)
//   albedo not divided by pi                         -> closed box (energy bound)
//   no division by the light pdf                     -> closed box
//   shadow ray never stopped (max_t infinite)        -> closed box (no growth with -m)
//   -m 1 traces a bounce (depth test off by one)     -> part 4 with -m 1 renders part 3
//   samples below the surface not skipped            -> part 4 renders (negative radiance)
//   zero light pdf not skipped (NaN)                 -> part 4 renders, Russian roulette, -o 0
//                                                       sum, closed box, -m 1 renders part 3
#include <catch2/catch.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "common/collada.h"
#include "stages/part2_bvh/bvh.h"
#include "common/lights.h"
#include "stages/part4_global_illumination/global_illumination.h"
#include "pathtracer/render_job.h"
#include "tests/statistics/analytic_scenes.h"
#include "tests/statistics/hypothesis_tests.h"
#include "tests/statistics/special_functions.h"
#include "common/stats.h"
#include "tests/support.h"

using namespace pt;
using namespace pt::test;

namespace {

constexpr double kAlpha = 0.01;
constexpr int kTests = 114;
const double kAlphaEach = sidak(kAlpha, kTests);

RenderOptions render_options(int w, int h, int spp, int max_depth, uint64_t seed) {
  RenderOptions o;
  o.part = 4;
  o.width = w;
  o.height = h;
  o.samples_per_pixel = spp;
  o.light_samples = 1;
  o.max_depth = max_depth;
  o.seed = seed;
  o.threads = 2;
  o.progress = false;
  return o;
}

bool valid_radiance(const Color& c) {
  return std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z) && c.x >= 0 && c.y >= 0 && c.z >= 0;
}

void check_valid(const ImageBuffer& img, const std::string& what) {
  int bad = 0;
  for (const Color& c : img.pixels) bad += valid_radiance(c) ? 0 : 1;
  INFO(what << ": " << bad << " pixels NaN, infinite or negative");
  CHECK(bad == 0);
}

void check_welch(const std::vector<double>& a, const std::vector<double>& b, const std::string& what) {
  const WelchTest w = welch_test(a, b);
  std::ostringstream o;
  o << what << ": difference " << w.difference << " +- " << w.std_error << ", t = " << w.t << " (" << w.dof
    << " dof), p = " << w.p_value << ", level " << kAlphaEach;
  stats_log(o.str());
  INFO(o.str());
  CHECK(w.p_value >= kAlphaEach);
}

void check_blocks(const std::vector<std::vector<double>>& a, const std::vector<std::vector<double>>& b,
                  const std::string& what) {
  const BlockComparison c = compare_blocks(a, b, kAlphaEach);
  stats_log(what + ": smallest block p " + std::to_string(c.min_p) + ", rejected " + std::to_string(c.rejected) +
            "\n" + c.report);
  INFO(what << ": " << c.blocks << " blocks, smallest p = " << c.min_p << ", level " << kAlphaEach << "\n" << c.report);
  CHECK(c.blocks == 48);
  CHECK(c.rejected == 0);
}

Scene course_view_scene(const std::string& name, int w, int h) {
  Scene s = load_collada(project_scene(name));
  fit_course_view(s.camera, w, h);
  return s;
}

// A closed box [-1, 1] x [0, 1.5] x [-1, 1] whose six walls all have albedo
// `albedo`, lit by a small 0.2 x 0.2 area light of radiance `L` under the
// ceiling (with its emissive quad), seen from inside.
Scene closed_box(float albedo, float L) {
  Scene s;
  const int m = add_material(s, diffuse_material(Color(albedo)));
  add_quad(s, Vec3(-1, 0, 1), Vec3(2, 0, 0), Vec3(0, 0, -2), Vec3(0, 1, 0), m);      // floor
  add_quad(s, Vec3(-1, 1.5f, -1), Vec3(2, 0, 0), Vec3(0, 0, 2), Vec3(0, -1, 0), m);  // ceiling
  add_quad(s, Vec3(-1, 0, -1), Vec3(2, 0, 0), Vec3(0, 1.5f, 0), Vec3(0, 0, 1), m);   // back
  add_quad(s, Vec3(1, 0, 1), Vec3(-2, 0, 0), Vec3(0, 1.5f, 0), Vec3(0, 0, -1), m);   // front
  add_quad(s, Vec3(-1, 0, 1), Vec3(0, 0, -2), Vec3(0, 1.5f, 0), Vec3(1, 0, 0), m);   // left
  add_quad(s, Vec3(1, 0, -1), Vec3(0, 0, 2), Vec3(0, 1.5f, 0), Vec3(-1, 0, 0), m);   // right
  add_area_light_with_quad(s, area_light(Vec3(0.3f, 1.49f, -0.2f), Vec3(0.2f, 0, 0), Vec3(0, 0, 0.2f),
                                         Vec3(0, -1, 0), Color(L)));
  aim_camera(s.camera, Vec3d(0, 0.75, 0.95), Vec3d(0, 0.6, -1), 70.0, 32, 24);
  return s;
}

// An integrating sphere: the inside of a closed diffuse sphere of albedo
// `albedo` (an icosphere of 5,120 triangles, radius 1, facing inward), lit
// by a small one-sided 0.1 x 0.1 area light of radiance `L` at its centre
// facing down (no quad: ours never hits a light with a ray), seen from
// inside. `area` receives the mesh's surface area.
Scene integrating_sphere(float albedo, float L, double* area) {
  Scene s;
  const int m = add_material(s, diffuse_material(Color(albedo)));
  const double g = (1 + std::sqrt(5.0)) / 2;
  std::vector<Vec3d> v = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                          {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  std::vector<std::array<int, 3>> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                       {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                       {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                       {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (Vec3d& p : v) p = normalize(p);
  for (int level = 0; level < 4; ++level) {
    std::map<std::pair<int, int>, int> middle;
    auto mid = [&](int a, int b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      const auto it = middle.find(key);
      if (it != middle.end()) return it->second;
      v.push_back(normalize(v[size_t(a)] + v[size_t(b)]));
      return middle[key] = int(v.size()) - 1;
    };
    std::vector<std::array<int, 3>> finer;
    for (const auto& t : f) {
      const int ab = mid(t[0], t[1]), bc = mid(t[1], t[2]), ca = mid(t[2], t[0]);
      finer.insert(finer.end(), {{t[0], ab, ca}, {t[1], bc, ab}, {t[2], ca, bc}, {ab, bc, ca}});
    }
    f = finer;
  }
  *area = 0;
  for (const auto& t : f) {
    const Vec3d a = v[size_t(t[0])], b = v[size_t(t[1])], c = v[size_t(t[2])];
    const Vec3d n = cross(b - a, a - c);  // a, c, b: wound to face inward
    *area += 0.5 * norm(n);
    Triangle tri;
    tri.p1 = Vec3(a);
    tri.p2 = Vec3(c);
    tri.p3 = Vec3(b);
    tri.n1 = tri.n2 = tri.n3 = Vec3(normalize(n));
    tri.material = m;
    s.triangles.push_back(tri);
  }
  s.lights.push_back(area_light(Vec3(0, 0, 0), Vec3(0.1f, 0, 0), Vec3(0, 0, 0.1f), Vec3(0, -1, 0), Color(L)));
  aim_camera(s.camera, Vec3d(0, 0.3, 0), Vec3d(0, 0.3, -1), 60.0, 32, 24);
  return s;
}

}  // namespace

TEST_CASE("a convex diffuse sphere under the ambient light has the same mean image with -m 1 and -m 5",
          "[part4][gi][ambient]") {
  const int w = 32, h = 24, seeds = 16;
  const Scene scene = course_view_scene("sphere_ambient.dae", w, h);
  for (bool hemisphere : {false, true}) {
    std::vector<double> one, five;
    for (int s = 0; s < seeds; ++s) {
      RenderOptions o = render_options(w, h, 4, 1, 100 + s);
      o.hemisphere_sampling = hemisphere;
      const RenderResult r1 = render_scene(scene, o);
      o.max_depth = 5;
      o.seed = 200 + s;
      const RenderResult r5 = render_scene(scene, o);
      check_valid(r5.image, "-m 5");
      one.push_back(image_mean(r1.image));
      five.push_back(image_mean(r5.image));
    }
    check_welch(one, five, hemisphere ? "-H, -m 1 against -m 5" : "light sampling, -m 1 against -m 5");
  }
}

TEST_CASE("Russian roulette on and off agree in mean at -m 5 on CBspheres_lambertian.dae, by 8x8 blocks",
          "[part4][gi][roulette]") {
  const int w = 64, h = 48, seeds = 16;
  const Scene scene = course_view_scene("CBspheres_lambertian.dae", w, h);
  std::vector<std::vector<double>> on, off;
  std::vector<double> on_mean, off_mean;
  for (int s = 0; s < seeds; ++s) {
    RenderOptions o = render_options(w, h, 4, 5, 300 + s);
    const RenderResult a = render_scene(scene, o);
    o.russian_roulette = false;
    o.seed = 400 + s;
    const RenderResult b = render_scene(scene, o);
    on.push_back(block_means(a.image, 8));
    off.push_back(block_means(b.image, 8));
    on_mean.push_back(image_mean(a.image));
    off_mean.push_back(image_mean(b.image));
  }
  double on_total = 0, off_total = 0;
  for (int s = 0; s < seeds; ++s) on_total += on_mean[size_t(s)], off_total += off_mean[size_t(s)];
  INFO("with Russian roulette the image is " << on_total / off_total << " times as bright as without. "
       << (on_total < off_total
               ? "Hint: darker with roulette? A path that survives must divide what it brings back by the "
                 "probability of continuing (kContinueProbability, 0.7); the first bounce from a camera ray "
                 "always continues."
               : "Hint: brighter with roulette? Divide by the probability of continuing once per bounce that "
                 "played roulette, not at bounces that always continue."));
  check_blocks(on, off, "roulette on against off");
  check_welch(on_mean, off_mean, "roulette on against off, image mean");
}

TEST_CASE("the -o 0 images for m = 0..5 sum to the -o 1 image at -m 5 in mean, by 8x8 blocks",
          "[part4][gi][accumulate]") {
  const int w = 64, h = 48, seeds = 16;
  const Scene scene = course_view_scene("CBspheres_lambertian.dae", w, h);
  std::vector<std::vector<double>> sums, totals;
  std::vector<double> sum_mean, total_mean;
  for (int s = 0; s < seeds; ++s) {
    ImageBuffer sum(w, h);
    for (int m = 0; m <= 5; ++m) {
      RenderOptions o = render_options(w, h, 4, m, 500 + 10 * s + m);
      o.accumulate_bounces = false;
      const RenderResult r = render_scene(scene, o);
      for (size_t i = 0; i < sum.pixels.size(); ++i) sum.pixels[i] += r.image.pixels[i];
    }
    const RenderResult total = render_scene(scene, render_options(w, h, 4, 5, 700 + s));
    sums.push_back(block_means(sum, 8));
    totals.push_back(block_means(total.image, 8));
    sum_mean.push_back(image_mean(sum));
    total_mean.push_back(image_mean(total.image));
  }
  check_blocks(sums, totals, "sum of -o 0 against -o 1");
  check_welch(sum_mean, total_mean, "sum of -o 0 against -o 1, image mean");
}

TEST_CASE("a closed box of albedo 0.5 stays finite and brightens monotonically with -m, within the energy bound per bounce",
          "[part4][gi][energy]") {
  const float albedo = 0.5f, L = 20.0f;
  const Scene scene = closed_box(albedo, L);
  const int w = 32, h = 24, seeds = 8, max_m = 6;
  // means[m][s]: image mean at -m m for seed s (the same seed for every m).
  std::vector<std::vector<double>> means(max_m + 1);
  for (int m = 0; m <= max_m; ++m)
    for (int s = 0; s < seeds; ++s) {
      const RenderResult r = render_scene(scene, render_options(w, h, 4, m, 800 + s));
      check_valid(r.image, "-m " + std::to_string(m));
      means[size_t(m)].push_back(image_mean(r.image));
    }
  const double t_crit = student_t_upper_quantile(kAlphaEach, seeds - 1);
  // Energy bound. One reflection of radiance at most X gives at most
  // rho X (the box is closed and every wall has albedo rho), and the first
  // reflection of the light gives at most rho / pi E_max, with E_max the
  // largest irradiance the light sends to any wall (Lambert's formula,
  // ignoring occlusion, maximised over a 61 x 61 grid on each wall, plus 2%
  // for the grid). So the m-th bounce adds at most rho^(m-1) rho E_max / pi
  // to any pixel, hence to the image mean.
  double e_max = 0;
  const Light& light = scene.lights[0];
  for (size_t t = 0; t < scene.triangles.size(); t += 2) {
    const Triangle& tri = scene.triangles[t];
    if (scene.materials[size_t(tri.material)].is_emissive()) continue;
    const Vec3 e1 = tri.p2 - tri.p1, e2 = tri.p3 - tri.p2;  // the quad's two edges
    for (int i = 0; i <= 60; ++i)
      for (int j = 0; j <= 60; ++j)
        e_max = std::max(e_max, area_light_irradiance(light, tri.p1 + e1 * (i / 60.0f) + e2 * (j / 60.0f), tri.n1, L));
  }
  const double first_bounce_max = 1.02 * albedo / M_PI * e_max;
  for (int m = 1; m <= max_m; ++m) {
    std::vector<double> gain, excess;
    const double bound = std::pow(double(albedo), m - 1) * first_bounce_max;
    for (int s = 0; s < seeds; ++s) {
      gain.push_back(means[size_t(m)][size_t(s)] - means[size_t(m - 1)][size_t(s)]);
      excess.push_back(gain.back() - bound);
    }
    const OneSampleT up = t_test_positive(gain), over = t_test_positive(excess);
    std::ostringstream o;
    o << "-m " << m << ": image mean " << means[size_t(m)][0] << " (first seed), gain over -m " << m - 1 << " = "
      << up.mean << " +- " << up.std_error << " (t = " << up.t << ", p = " << up.p_upper << "), bound "
      << bound << " (t = " << over.t << ", p = " << over.p_upper << "), level " << kAlphaEach << ", t crit "
      << t_crit;
    stats_log(o.str());
    INFO(o.str());
    CHECK(up.p_upper < kAlphaEach);       // significantly brighter than with one bounce fewer
    CHECK(over.p_upper >= kAlphaEach);    // and not significantly above the energy bound
  }
}

TEST_CASE("the indirect light inside a closed diffuse sphere is the integrating sphere's, bounce by bounce",
          "[part4][gi][energy]") {
  // Inside a sphere every patch sends the same share of what it reflects to
  // every other patch (the form factor dA / A), so light reflected once or
  // more is uniform: the light's flux Phi = pi L a (a = its area) reflected
  // k - 1 times gives irradiance rho^(k-1) Phi / A everywhere, and the path
  // of k bounces adds rho^k Phi / (pi A) to every pixel. With -m m and
  // --indirect-only (bounces 2..m) the image is uniformly
  // Phi / (pi A) (rho^2 + ... + rho^m). The mesh's own area stands for
  // 4 pi: its flat facets bias the value by +0.06 % +- 0.04 % (measured at
  // 6.3 million paths), far below this test's standard error (about 0.3 %).
  const float albedo = 0.5f, L = 10.0f;
  double area = 0;
  const Scene scene = integrating_sphere(albedo, L, &area);
  const double flux = M_PI * L * 0.1 * 0.1;
  const int w = 32, h = 24, seeds = 16;
  for (int m : {2, 5}) {
    double expected = 0;
    for (int k = 2; k <= m; ++k) expected += std::pow(double(albedo), k) * flux / (M_PI * area);
    std::vector<double> ratio;
    for (int s = 0; s < seeds; ++s) {
      RenderOptions o = render_options(w, h, 8, m, 1300 + 20 * s + m);
      o.indirect_only = true;
      const RenderResult r = render_scene(scene, o);
      check_valid(r.image, "-m " + std::to_string(m));
      ratio.push_back(image_mean(r.image) / expected - 1);
    }
    const OneSampleT t = t_test_positive(ratio);
    const double p = 2 * std::min(t.p_upper, 1 - t.p_upper);
    std::ostringstream o;
    o << "-m " << m << " --indirect-only: image mean / expected - 1 = " << t.mean << " +- " << t.std_error
      << " (expected " << expected << ", t = " << t.t << ", two-sided p = " << p << "), level " << kAlphaEach;
    stats_log(o.str());
    INFO(o.str());
    CHECK(p >= kAlphaEach);
  }
}

TEST_CASE("part 4 with -m 1 renders exactly the part 3 image", "[part4][gi][depth]") {
  const int w = 32, h = 24;
  const Scene scene = course_view_scene("CBspheres_lambertian.dae", w, h);
  for (bool hemisphere : {false, true}) {
    RenderOptions o = render_options(w, h, 2, 1, 900);
    o.light_samples = 2;
    o.hemisphere_sampling = hemisphere;
    const RenderResult four = render_scene(scene, o);
    o.part = 3;
    const RenderResult three = render_scene(scene, o);
    int differ = 0;
    for (size_t i = 0; i < four.image.pixels.size(); ++i) differ += four.image.pixels[i] == three.image.pixels[i] ? 0 : 1;
    INFO((hemisphere ? "-H: " : "light sampling: ") << differ << " pixels differ");
    CHECK(differ == 0);
  }
}

TEST_CASE("part 4 renders of every project scene have no NaN, infinite or negative radiance", "[part4][gi][sanity]") {
  int scenes = 0;
  for (const std::string& name : list_dir(PT_PROJECT_SCENES)) {
    if (name.size() < 4 || name.substr(name.size() - 4) != ".dae") continue;
    ++scenes;
    const Scene scene = course_view_scene(name, 32, 24);
    // Light sampling summing the bounces, and -H with the last bounce only
    // (each render rebuilds the BVH, the bulk of the time on the big meshes).
    for (bool hemisphere : {false, true}) {
      RenderOptions o = render_options(32, 24, 4, 4, 1000);
      o.light_samples = 2;
      o.hemisphere_sampling = hemisphere;
      o.accumulate_bounces = !hemisphere;
      check_valid(render_scene(scene, o).image, name + (hemisphere ? " -H -o 0" : " -o 1") + " -m 4");
    }
  }
  CHECK(scenes >= 5);
}

TEST_CASE("a path of a million bounces without Russian roulette runs in constant stack (-m 1000000 --no-rr)",
          "[part4][gi][depth]") {
  // Between two facing diffuse planes 200,000 units wide and 1 apart, with
  // no light, every bounce hits a plane again: a bounce leaves the gap only
  // at a grazing angle (cos < 1e-5, probability 1e-10 per bounce), so paths
  // run to their full depth. (A closed box would not do: a bounce starting
  // within the ray epsilon of a corner leaks through it, about once in
  // 10^3-10^4 bounces.) A path traced by recursion needs a stack frame per
  // bounce (some 100 MB here) and crashes; a loop needs none.
  Scene scene;
  const int m = add_material(scene, diffuse_material(Color(0.5f)));
  const float w = 1e5f;
  add_quad(scene, Vec3(-w, 0, w), Vec3(2 * w, 0, 0), Vec3(0, 0, -2 * w), Vec3(0, 1, 0), m);  // floor
  add_quad(scene, Vec3(-w, 1, -w), Vec3(2 * w, 0, 0), Vec3(0, 0, 2 * w), Vec3(0, -1, 0), m); // ceiling
  aim_camera(scene.camera, Vec3d(0, 0.5, 0), Vec3d(0, 0.4, -1), 60.0, 1, 1);
  BVH bvh(scene);
  const ShadingContext ctx{scene, bvh};
  PathOptions opts;
  opts.max_depth = 1000000;
  opts.russian_roulette = false;
  thread_ray_stats() = RayStats{};
  Rng rng = Rng::for_sample(1, 0, 0);
  const Ray camera_ray(Vec3(0, 0.5f, 0), normalize(Vec3(0, -0.5f, -1)), 0.0f, kInfinity);
  const Color L = est_radiance_global_illumination(ctx, opts, camera_ray, rng);
  CHECK(L.x == 0.0f);  // no light
  // One closest-hit query per bounce: the camera ray, then 999,999 bounces.
  CHECK(thread_ray_stats().closest_queries == 1000000u);

  // The same through whole renders on the render threads (parts 4 and 5).
  for (int part : {4, 5}) {
    RenderOptions o = render_options(1, 1, 1, 1000000, 7);
    o.part = part;
    o.russian_roulette = false;
    const RenderResult r = render_scene(scene, o);
    INFO("--part " << part);
    CHECK(r.stats.closest_queries == 1000000u);
  }
}
