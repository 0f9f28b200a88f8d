// Part 3: direct lighting by hemisphere sampling (-H) and by light sampling,
// through the real estimators, against closed forms and against each other.
//
// Statistics: one family per file at alpha = 0.01, Sidak-corrected over its
// K = 111 tests (each at 1 - 0.99^(1/111) = 9.05e-5), fixed seeds:
//   10  z tests: a diffuse plane under a rectangular area light, five points,
//       light sampling (200,000 estimates each) and -H (1,000,000 each),
//       against Lambert's polygon formula;
//    1  z test: plane_arealight.dae at the image centre (200,000 estimates);
//    4  z tests: a diffuse surface under the ambient light, facing up and
//       tilted, light sampling and -H (200,000 estimates each);
//   48  Welch t tests: -H against light sampling on 8x8 blocks of a 64x48
//       render of a Cornell box built in code whose emissive quad is its
//       area light (16 seeds per estimator, 16 spp, -l 8);
//   48  Welch t tests: the same on CBspheres_lambertian.dae, whose emissive
//       quad covers exactly the light's rectangle and whose backing plate
//       hides the quad's back (which -H would count and the one-sided light
//       does not).
// Delta lights are checked exactly (zero variance); the remaining checks
// are deterministic.
//
// Deliberate bug (planted in a scratch copy) -> tests here that failed on it:
//   missing cosine, light sampling      -> Lambert light sampling, plane_arealight.dae, ambient,
//                                          delta lights, agree in a Cornell box
//   missing cosine, -H                  -> Lambert -H, ambient, agree in a Cornell box
//   albedo not divided by pi            -> Lambert light sampling and -H, plane_arealight.dae,
//                                          ambient, delta lights
//   wrong hemisphere pdf (1/pi)         -> Lambert -H, ambient, agree in a Cornell box
//   uniform hemisphere z = sqrt(u1)     -> Lambert -H, ambient, agree in a Cornell box
//   no division by the light pdf        -> Lambert light sampling, plane_arealight.dae, ambient,
//                                          agree in a Cornell box
//   area light point over +-dim         -> Lambert light sampling, plane_arealight.dae,
//                                          agree in a Cornell box
//   area light pdf without its cosine   -> Lambert light sampling, plane_arealight.dae,
//                                          agree in a Cornell box
//   samples below the surface not       -> Lambert light sampling (the vertical card), ambient
//     skipped                              (the tilted card), part 3 renders (negative radiance)
//   no shadow-ray epsilon (min_t = 0)   -> no shadow acne, Lambert light sampling, ambient, delta
//                                          lights, agree in a Cornell box
//   shadow ray not stopped at the light -> Lambert light sampling, agree in a Cornell box
//     (max_t = distance, or infinite)
//   delta light sampled -l times        -> delta lights (one shadow ray each); says so
//   shadow ray min_t = 1e-11 (the       -> no shadow acne, delta lights (the shadowed point),
//     course's EPS_D, no offset in float)  agree in both Cornell boxes; the failures say so
//   -H ignores the emission it hits     -> Lambert -H, agree in a Cornell box
//   Frame::from_normal wrong for n.z<0  -> agree in a Cornell box
//   zero light pdf not skipped (NaN)    -> part 3 renders of every project scene, agree in a
//                                          Cornell box
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "stages/part1_raytracing/brute_force.h"
#include "stages/part2_bvh/bvh.h"
#include "stages/part1_raytracing/camera_rays.h"
#include "common/collada.h"
#include "stages/part3_direct_lighting/direct_lighting.h"
#include "common/frame.h"
#include "pathtracer/render_job.h"
#include "common/samplers.h"
#include "tests/statistics/analytic_scenes.h"
#include "tests/statistics/hypothesis_tests.h"
#include "tests/support.h"

using namespace pt;
using namespace pt::test;

namespace {

constexpr double kAlpha = 0.01;
constexpr int kTests = 111;
const double kAlphaEach = sidak(kAlpha, kTests);

// Counts the queries the estimators make.
class CountingIntersector final : public Intersector {
 public:
  explicit CountingIntersector(const Intersector& inner) : inner_(inner) {}
  bool intersect(Ray& r, Hit* hit) const override {
    ++closest;
    return inner_.intersect(r, hit);
  }
  bool occluded(const Ray& r) const override {
    ++shadow;
    return inner_.occluded(r);
  }
  mutable long long closest = 0, shadow = 0;

 private:
  const Intersector& inner_;
};

// A shading point: the ray that found it and its hit record.
struct ShadingPoint {
  Ray ray;
  Hit hit;
  Vec3 p, n;
  std::string name;
};

// The point where the ray from `eye` toward `target` hits the scene.
ShadingPoint traced_point(const Intersector& geometry, const Vec3& eye, const Vec3& target, const std::string& name) {
  ShadingPoint s;
  s.ray = Ray(eye, normalize(target - eye));
  REQUIRE(geometry.intersect(s.ray, &s.hit));
  s.p = s.ray.at(s.hit.t);
  s.n = s.hit.n;
  s.name = name;
  return s;
}

// A point of a surface with normal n that is not part of the geometry
// (an infinitely thin card): seen along -n from one unit away.
ShadingPoint card_point(const Vec3& p, const Vec3& n, int material, const std::string& name) {
  ShadingPoint s;
  s.ray = Ray(p + n, -n);
  s.hit.t = 1.0f;
  s.hit.n = n;
  s.hit.material = material;
  s.p = s.ray.at(1.0f);
  s.n = n;
  s.name = name;
  return s;
}

struct Estimates {
  RunningStats x;          // red channel
  double sum_y = 0, sum_z = 0;
};

Estimates estimate(const ShadingContext& ctx, const ShadingPoint& sp, int n, uint64_t seed) {
  Estimates e;
  Rng rng(seed);
  for (int i = 0; i < n; ++i) {
    const Color c = ctx.hemisphere ? estimate_direct_lighting_hemisphere(ctx, sp.ray, sp.hit, rng)
                                   : estimate_direct_lighting_importance(ctx, sp.ray, sp.hit, rng);
    e.x.add(c.x);
    e.sum_y += c.y;
    e.sum_z += c.z;
  }
  return e;
}

// z test of the red channel against `expected`; the green and blue means
// must be in the ratio the colours prescribe.
// What to look at when an estimator's mean is off (shown with a failure).
const char* const kLightSamplingHint =
    "Hint: far too dark? A shadow ray starts at the hit point with min_t = kRayEpsilon (the course's EPS_D, "
    "1e-11, is no offset at all in a float ray: it finds its own surface) and stops at max_t = distance - "
    "kRayEpsilon (here an emissive quad lies exactly where the light is: a shadow ray that goes all the way "
    "hits it). Off by a factor? Each sample adds f L cos theta / pdf, with the pdf sample_light gives "
    "(per solid angle), averaged over the light's samples.";
const char* const kHemisphereHint =
    "Hint: each direction is uniform over the hemisphere, pdf 1 / (2 pi), and adds f L cos theta / pdf, "
    "averaged over every sample; a direction's ray starts at kRayEpsilon, so that it does not find the "
    "surface it leaves.";

void check_mean(const Estimates& e, double expected, double ratio_y, double ratio_z, const char* hint) {
  const ZTest z = z_test(e.x, expected);
  {
    std::ostringstream o;
    o << "mean " << e.x.mean << " expected " << expected << " se " << e.x.std_error() << " z " << z.z << " p "
      << z.p_value;
    stats_log(o.str());
  }
  INFO("mean " << e.x.mean << " +- " << e.x.std_error() << " (n = " << e.x.n << "), expected " << expected
               << " (yours is " << e.x.mean / expected << " times that), z = " << z.z << ", p = " << z.p_value
               << ", level " << kAlphaEach << ". " << hint);
  CHECK(z.p_value >= kAlphaEach);
  const double n = double(e.x.n);
  if (e.x.mean != 0) {
    CHECK(e.sum_y / n / e.x.mean == Approx(ratio_y).epsilon(1e-3));
    CHECK(e.sum_z / n / e.x.mean == Approx(ratio_z).epsilon(1e-3));
  }
}

// A 6 x 6 diffuse plane at y = 0 (albedo 0.5, 0.35, 0.2) under a one-sided
// 1.0 x 0.6 area light at height 0.8 facing down (radiance 2, 1, 4), with
// an emissive quad covering exactly the light so that -H sees it.
const Color kPlaneAlbedo(0.5f, 0.35f, 0.2f);
const Color kLightRadiance(2.0f, 1.0f, 4.0f);
Scene plane_under_area_light() {
  Scene s;
  const int plane = add_material(s, diffuse_material(kPlaneAlbedo));
  add_quad(s, Vec3(-3, 0, 3), Vec3(6, 0, 0), Vec3(0, 0, -6), Vec3(0, 1, 0), plane);
  add_area_light_with_quad(s, area_light(Vec3(0.2f, 0.8f, -0.1f), Vec3(1.0f, 0, 0), Vec3(0, 0, 0.6f),
                                         Vec3(0, -1, 0), kLightRadiance));
  return s;
}

// Five points: four on the plane (below the light's centre, below one of
// its corners, beside it and far off at a grazing angle) found by tracing,
// and one on a vertical card facing +x that sees only part of the light
// above its horizon.
std::vector<ShadingPoint> plane_points(const Scene& s, const Intersector& geometry) {
  std::vector<ShadingPoint> pts;
  const Vec3 up_back(0, 2, 2);
  for (const auto& t : std::vector<std::pair<Vec3, std::string>>{{Vec3(0.2f, 0, -0.1f), "below the centre"},
                                                                  {Vec3(0.7f, 0, -0.4f), "below a corner"},
                                                                  {Vec3(1.1f, 0, 0.45f), "beside the light"},
                                                                  {Vec3(-1.5f, 0, 1.2f), "far, grazing"}})
    pts.push_back(traced_point(geometry, t.first + up_back, t.first, t.second));
  pts.push_back(card_point(Vec3(0.4f, 0.5f, -0.1f), Vec3(1, 0, 0), s.triangles[0].material,
                           "vertical card, light partly below its horizon"));
  return pts;
}

double lambert_radiance(const Light& l, const ShadingPoint& sp, double albedo, double L) {
  return albedo / M_PI * area_light_irradiance(l, sp.p, sp.n, L);
}

RenderOptions render_options(int part, int w, int h, int spp, int light_samples, uint64_t seed) {
  RenderOptions o;
  o.part = part;
  o.width = w;
  o.height = h;
  o.samples_per_pixel = spp;
  o.light_samples = light_samples;
  o.seed = seed;
  o.threads = 2;
  o.progress = false;
  return o;
}

// The course's Cornell box (walls, two spheres of albedo 0.8), open at the
// front, lit by a 0.6 x 0.8 area light of radiance 10 set into a hole of
// the ceiling and filled by an emissive quad that is exactly its rectangle.
// Flush with the ceiling, the quad's back faces out of the box: no surface
// sees it (-H sees emission from both sides of a quad, while the area light
// emits only downward).
Scene cornell_box_with_matching_light() {
  Scene s;
  const int grey = add_material(s, diffuse_material(Color(0.6f)));
  const int red = add_material(s, diffuse_material(Color(0.6f, 0.2f, 0.2f)));
  const int blue = add_material(s, diffuse_material(Color(0.2f, 0.2f, 0.6f)));
  const int white = add_material(s, diffuse_material(Color(0.8f)));
  const Vec3 down(0, -1, 0);
  add_quad(s, Vec3(-1, 0, 1), Vec3(2, 0, 0), Vec3(0, 0, -2), Vec3(0, 1, 0), grey);     // floor
  add_quad(s, Vec3(-1, 0, -1), Vec3(2, 0, 0), Vec3(0, 1.5f, 0), Vec3(0, 0, 1), grey);  // back
  add_quad(s, Vec3(-1, 0, 1), Vec3(0, 0, -2), Vec3(0, 1.5f, 0), Vec3(1, 0, 0), red);   // left
  add_quad(s, Vec3(1, 0, -1), Vec3(0, 0, 2), Vec3(0, 1.5f, 0), Vec3(-1, 0, 0), blue);  // right
  // The ceiling around the hole x in [-0.3, 0.3], z in [-0.4, 0.4].
  add_quad(s, Vec3(-1, 1.5f, -1), Vec3(0.7f, 0, 0), Vec3(0, 0, 2), down, grey);
  add_quad(s, Vec3(0.3f, 1.5f, -1), Vec3(0.7f, 0, 0), Vec3(0, 0, 2), down, grey);
  add_quad(s, Vec3(-0.3f, 1.5f, -1), Vec3(0.6f, 0, 0), Vec3(0, 0, 0.6f), down, grey);
  add_quad(s, Vec3(-0.3f, 1.5f, 0.4f), Vec3(0.6f, 0, 0), Vec3(0, 0, 0.6f), down, grey);
  s.spheres.push_back(Sphere{Vec3(0.4f, 0.3f, 0.3f), 0.3f, white});
  s.spheres.push_back(Sphere{Vec3(-0.4f, 0.3f, -0.3f), 0.3f, white});
  add_area_light_with_quad(s, area_light(Vec3(0, 1.5f, 0), Vec3(0.6f, 0, 0), Vec3(0, 0, 0.8f), down, Color(10.0f)));
  aim_camera(s.camera, Vec3d(0, 0.75, 4.80234), Vec3d(0, 0.75, 0), 37.8493, 64, 48);
  return s;
}

// Renders `seeds` images of `scene` at part 3 with each estimator and tests
// their 8x8 block means against each other.
void check_hemisphere_agrees_with_light_sampling(const Scene& scene) {
  const int w = 64, h = 48, spp = 16, light_samples = 8, seeds = 16;
  std::vector<std::vector<double>> hemi, lights;
  for (int s = 0; s < seeds; ++s) {
    RenderOptions o = render_options(3, w, h, spp, light_samples, 1000 + s);
    o.hemisphere_sampling = true;
    hemi.push_back(block_means(render_scene(scene, o).image, 8));
    o.hemisphere_sampling = false;
    o.seed = 2000 + s;
    lights.push_back(block_means(render_scene(scene, o).image, 8));
  }
  const BlockComparison c = compare_blocks(hemi, lights, kAlphaEach);
  stats_log("blocks: smallest p " + std::to_string(c.min_p) + ", rejected " + std::to_string(c.rejected) + "\n" +
            c.report);
  double hemi_sum = 0, light_sum = 0;
  for (const auto& image : hemi)
    for (double b : image) hemi_sum += b;
  for (const auto& image : lights)
    for (double b : image) light_sum += b;
  INFO(c.blocks << " blocks, smallest p = " << c.min_p << ", level " << kAlphaEach << "\n" << c.report
                << "(each block: -H's mean vs light sampling's)\nThe light-sampled image is " << light_sum / hemi_sum
                << " times as bright as the -H one. "
                << (light_sum < hemi_sum
                        ? "Hint: light sampling too dark? Its shadow rays must stop at distance - kRayEpsilon (an "
                          "emissive quad lies exactly where the area light is: a shadow ray that reaches it is "
                          "blocked) and start at kRayEpsilon; each light's samples are averaged, the lights summed."
                        : "Hint: light sampling too bright, or -H too dark? Check the pdfs (1 / (2 pi) for -H, "
                          "sample_light's for light sampling), cos theta, and that each estimator divides by its "
                          "own number of samples (-H: lights x -l)."));
  CHECK(c.blocks == 48);
  CHECK(c.rejected == 0);
}

// Whether -H and light sampling estimate the same scene: the emissive
// triangles cover exactly the rectangle of the one area light, with its
// radiance, and no surface sees their back (emission is seen from both sides
// of a triangle, an area light shines only along its direction). The back is
// probed with 64 x 64 rays from points on the light.
bool emissive_geometry_is_the_area_light(const Scene& s, std::string* why) {
  const Light* light = nullptr;
  for (const Light& l : s.lights)
    if (l.type == LightType::Area) light = &l;
  if (!light) {
    *why = "no area light";
    return false;
  }
  double area = 0;
  for (const Triangle& t : s.triangles) {
    const Material& m = s.materials[size_t(t.material)];
    if (!m.is_emissive()) continue;
    if (m.emission != light->radiance) {
      *why = "emission differs from the light's radiance";
      return false;
    }
    for (const Vec3& v : {t.p1, t.p2, t.p3}) {
      double a, b, dist;
      const Vec3d p = to_d(v) + to_d(light->direction) * 1e-3;  // just in front of the light
      if (!area_light_plane_hit(*light, p, normalize(to_d(light->direction) * -1.0), &a, &b, &dist) ||
          std::fabs(dist - 1e-3) > 1e-5 || std::fabs(a) > 0.5 + 1e-5 || std::fabs(b) > 0.5 + 1e-5) {
        std::ostringstream o;
        o << "emissive vertex (" << v.x << ", " << v.y << ", " << v.z << ") lies outside the area light's rectangle";
        *why = o.str();
        return false;
      }
    }
    area += 0.5 * norm(cross(to_d(t.p2) - to_d(t.p1), to_d(t.p3) - to_d(t.p1)));
  }
  const double light_area = norm(cross(to_d(light->dim_x), to_d(light->dim_y)));
  if (std::fabs(area - light_area) > 1e-4 * light_area) {
    *why = "emissive area differs from the light's area";
    return false;
  }
  const BVH bvh(s);
  const Frame back = Frame::from_normal(-light->direction);
  Rng rng(77);
  for (int i = 0; i < 64; ++i) {
    const Vec3 q = light->position + light->dim_x * (rng.uniform() - 0.5f) + light->dim_y * (rng.uniform() - 0.5f);
    for (int j = 0; j < 64; ++j) {
      Ray r(q, back.to_world(sample_uniform_hemisphere(rng.uniform(), rng.uniform())), 1e-3f);
      Hit hit;
      if (bvh.intersect(r, &hit) && !s.materials[size_t(hit.material)].is_emissive()) {
        const Vec3 p = r.at(hit.t);
        std::ostringstream o;
        o << "a surface behind the light, e.g. at (" << p.x << ", " << p.y << ", " << p.z
          << "), sees the back of the emissive quad";
        *why = o.str();
        return false;
      }
    }
  }
  return true;
}

bool valid_radiance(const Color& c) {
  return std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z) && c.x >= 0 && c.y >= 0 && c.z >= 0;
}

}  // namespace

TEST_CASE("light sampling matches Lambert's formula on a diffuse plane under an area light, z tests at five points",
          "[part3][direct][analytic]") {
  const Scene scene = plane_under_area_light();
  const BVH bvh(scene);
  ShadingContext ctx{scene, bvh};
  ctx.light_samples = 1;
  const Light& light = scene.lights[0];
  uint64_t seed = 11;
  for (const ShadingPoint& sp : plane_points(scene, bvh)) {
    INFO("point " << sp.name << " at " << sp.p.x << " " << sp.p.y << " " << sp.p.z);
    const double expected = lambert_radiance(light, sp, kPlaneAlbedo.x, kLightRadiance.x);
    REQUIRE(expected > 1e-3);
    check_mean(estimate(ctx, sp, 200000, seed++), expected, 0.35 * 1.0 / (0.5 * 2.0), 0.2 * 4.0 / (0.5 * 2.0),
               kLightSamplingHint);
  }
}

TEST_CASE("hemisphere sampling matches Lambert's formula on a diffuse plane under an area light, z tests at five points",
          "[part3][direct][analytic]") {
  const Scene scene = plane_under_area_light();
  const BVH bvh(scene);
  ShadingContext ctx{scene, bvh};
  ctx.light_samples = 1;
  ctx.hemisphere = true;
  const Light& light = scene.lights[0];
  uint64_t seed = 21;
  for (const ShadingPoint& sp : plane_points(scene, bvh)) {
    INFO("point " << sp.name << " at " << sp.p.x << " " << sp.p.y << " " << sp.p.z);
    const double expected = lambert_radiance(light, sp, kPlaneAlbedo.x, kLightRadiance.x);
    check_mean(estimate(ctx, sp, 1000000, seed++), expected, 0.35 * 1.0 / (0.5 * 2.0), 0.2 * 4.0 / (0.5 * 2.0),
               kHemisphereHint);
  }
}

TEST_CASE("plane_arealight.dae reflects 0.0367388 at the image centre with light sampling, z test",
          "[part3][direct][analytic][scene]") {
  Scene scene = load_collada(project_scene("plane_arealight.dae"));
  REQUIRE(scene.lights.size() == 1);
  const Light& light = scene.lights[0];
  // The closed form itself reproduces the scene README's numbers.
  CHECK(area_light_irradiance(light, Vec3(0.0f), Vec3(0, 1, 0), 1.0) == Approx(0.2308368).epsilon(1e-6));
  CHECK(0.5 / M_PI * area_light_irradiance(light, Vec3(0.0f), Vec3(0, 1, 0), 1.0) ==
        Approx(0.0367388).epsilon(1e-5));
  const BVH bvh(scene);
  ShadingPoint sp;
  sp.ray = generate_ray(scene.camera, 0.5, 0.5);
  REQUIRE(bvh.intersect(sp.ray, &sp.hit));
  sp.p = sp.ray.at(sp.hit.t);
  sp.n = sp.hit.n;
  REQUIRE(norm(sp.p) < 1e-3f);
  ShadingContext ctx{scene, bvh};
  ctx.light_samples = 1;
  check_mean(estimate(ctx, sp, 200000, 31), 0.0367388, 1.0, 1.0, kLightSamplingHint);
}

TEST_CASE("a diffuse surface under the ambient light reflects rho L facing up and rho L (1 + n_y)/2 tilted, z tests",
          "[part3][direct][analytic][ambient]") {
  Scene scene;
  const Color albedo(0.6f, 0.3f, 0.45f);
  const int m = add_material(scene, diffuse_material(albedo));
  add_quad(scene, Vec3(-2, 0, 2), Vec3(4, 0, 0), Vec3(0, 0, -4), Vec3(0, 1, 0), m);
  Light ambient;
  ambient.type = LightType::Ambient;
  ambient.radiance = Color(1.5f, 1.5f, 1.5f);
  scene.lights.push_back(ambient);
  const BruteForceIntersector geometry(scene);  // part 1's intersector serves as well as the BVH
  const std::vector<ShadingPoint> pts = {
      traced_point(geometry, Vec3(0.3f, 1.0f, 1.0f), Vec3(0.3f, 0, -0.2f), "plane facing up"),
      // A card tilted 60 degrees from +Y above the plane: part of the sky
      // lies below its horizon.
      card_point(Vec3(0.0f, 0.7f, 0.0f), normalize(Vec3(std::sin(1.0472f), std::cos(1.0472f), 0.0f)), m,
                 "card tilted 60 degrees")};
  uint64_t seed = 41;
  for (bool hemisphere : {false, true}) {
    ShadingContext ctx{scene, geometry};
    ctx.light_samples = 1;
    ctx.hemisphere = hemisphere;
    for (const ShadingPoint& sp : pts) {
      INFO((hemisphere ? "-H, " : "light sampling, ") << sp.name);
      const double expected = 0.6 * 1.5 * (1.0 + sp.n.y) / 2.0;
      check_mean(estimate(ctx, sp, 200000, seed++), expected, 0.5, 0.75,
                 hemisphere ? kHemisphereHint : kLightSamplingHint);
    }
  }
}

TEST_CASE("delta lights give the exact radiance with zero variance and one shadow ray each",
          "[part3][direct][analytic][delta]") {
  Scene scene;
  const Color albedo(0.5f, 0.25f, 0.8f);
  const int m = add_material(scene, diffuse_material(albedo));
  add_quad(scene, Vec3(-3, 0, 3), Vec3(6, 0, 0), Vec3(0, 0, -6), Vec3(0, 1, 0), m);
  Light point;
  point.type = LightType::Point;
  point.position = Vec3(0.3f, 1.5f, -0.2f);
  point.radiance = Color(4.0f, 2.0f, 1.0f);
  point.constant_attenuation = 1.0f;
  point.linear_attenuation = 0.3f;
  point.quadratic_attenuation = 0.2f;
  scene.lights.push_back(point);
  Light sun;
  sun.type = LightType::Directional;
  sun.direction = normalize(Vec3(0.3f, -1.0f, 0.4f));
  sun.radiance = Color(0.5f, 1.0f, 0.25f);
  scene.lights.push_back(sun);
  const BVH bvh(scene);
  const CountingIntersector counting(bvh);
  ShadingContext ctx{scene, counting};
  ctx.light_samples = 4;  // -l applies to area lights only
  Rng rng(51);
  for (const Vec3& target : {Vec3(0.3f, 0, -0.2f), Vec3(1.2f, 0, 0.7f), Vec3(-2.0f, 0, -1.5f)}) {
    const ShadingPoint sp = traced_point(bvh, target + Vec3(0.1f, 2.0f, 1.0f), target, "plane");
    const Vec3d to_light = to_d(point.position) - to_d(sp.p);
    const double d = norm(to_light);
    const double cos_point = to_light.y / d;
    const double cos_sun = -sun.direction.y;
    Color expected;
    for (int c = 0; c < 3; ++c)
      expected[c] = float(albedo[c] / M_PI *
                          (point.radiance[c] / (1.0 + 0.3 * d + 0.2 * d * d) * cos_point + sun.radiance[c] * cos_sun));
    for (int i = 0; i < 100; ++i) {
      counting.shadow = 0;
      const Color L = estimate_direct_lighting_importance(ctx, sp.ray, sp.hit, rng);
      INFO("at " << sp.p.x << " " << sp.p.z << ": " << L.x << " " << L.y << " " << L.z << " expected " << expected.x
                 << " " << expected.y << " " << expected.z);
      REQUIRE(L.x == Approx(expected.x).epsilon(1e-5));
      REQUIRE(L.y == Approx(expected.y).epsilon(1e-5));
      REQUIRE(L.z == Approx(expected.z).epsilon(1e-5));
      INFO("Hint: a point or directional light gives the same sample every time, so the course samples it once "
           "(one shadow ray), whatever -l: -l applies to area lights only.");
      REQUIRE(counting.shadow == 2);  // one shadow ray per delta light, whatever -l is
    }
  }
  // An area light added to the scene takes -l shadow rays (all its samples
  // are above the plane's horizon here).
  scene.lights.push_back(area_light(Vec3(0, 2, 0), Vec3(0.5f, 0, 0), Vec3(0, 0, 0.5f), Vec3(0, -1, 0), Color(1.0f)));
  const ShadingPoint sp = traced_point(bvh, Vec3(0.1f, 2, 1), Vec3(0, 0, 0), "plane");
  counting.shadow = 0;
  estimate_direct_lighting_importance(ctx, sp.ray, sp.hit, rng);
  CHECK(counting.shadow == 2 + 4);
  scene.lights.pop_back();
  // A blocker between the point and the point light removes exactly its share.
  Scene blocked = scene;
  add_quad(blocked, Vec3(0.1f, 1.0f, 0.0f), Vec3(0.4f, 0, 0), Vec3(0, 0, -0.4f), Vec3(0, -1, 0), m);
  const BVH bvh2(blocked);
  ShadingContext ctx2{blocked, bvh2};
  const ShadingPoint below = traced_point(bvh2, Vec3(0.3f, 0.5f, 1.0f), Vec3(0.3f, 0, -0.2f), "shadowed");
  const Color L = estimate_direct_lighting_importance(ctx2, below.ray, below.hit, rng);
  INFO("the plane under a card that hides the point light from it but not the sun: its light is the sun's alone. "
       "Hint: 0 here means the sun's shadow ray was blocked too: it must start at kRayEpsilon, not at the surface "
       "(min_t 0 or the course's 1e-11), and a directional light's shadow ray runs to infinity.");
  CHECK(L.x == Approx(albedo.x / M_PI * sun.radiance.x * -sun.direction.y).epsilon(1e-5));
}

TEST_CASE("every plane pixel receives light: no shadow acne on plane_arealight.dae, 1 spp",
          "[part3][direct][acne]") {
  Scene scene = load_collada(project_scene("plane_arealight.dae"));
  const int w = 64, h = 48;
  fit_course_view(scene.camera, w, h);
  const RenderResult r = render_scene(scene, render_options(3, w, h, 1, 1, 61));
  const BVH bvh(scene);
  int plane_pixels = 0, dark = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      Ray ray = generate_ray(scene.camera, (x + 0.5) / w, (y + 0.5) / h);
      Hit hit;
      const Color c = r.image.at(x, y);
      REQUIRE(valid_radiance(c));
      if (!bvh.intersect(ray, &hit)) continue;
      ++plane_pixels;
      if (!(c.x > 0)) ++dark;
    }
  INFO(dark << " of " << plane_pixels << " plane pixels got no light. Hint: speckles of black (shadow acne) come "
              "from shadow rays that find the surface they start on: start them at min_t = kRayEpsilon (1e-4); the "
              "course's EPS_D (1e-11) is no offset at all in a float ray.");
  CHECK(plane_pixels > w * h / 4);
  CHECK(dark == 0);
}

TEST_CASE("hemisphere and light sampling agree block by block in a Cornell box whose emissive quad is its area light",
          "[part3][direct][agreement]") {
  const Scene scene = cornell_box_with_matching_light();
  std::string why;
  const bool same_scene = emissive_geometry_is_the_area_light(scene, &why);
  INFO(why);
  REQUIRE(same_scene);
  check_hemisphere_agrees_with_light_sampling(scene);
}

TEST_CASE("hemisphere and light sampling agree block by block on CBspheres_lambertian.dae",
          "[part3][direct][agreement][scene]") {
  // The scene's emissive quad covers the area light exactly and a backing
  // plate hides its back (scenes/README.md), so both estimators see the
  // same light.
  Scene scene = load_collada(project_scene("CBspheres_lambertian.dae"));
  fit_course_view(scene.camera, 64, 48);
  check_hemisphere_agrees_with_light_sampling(scene);
}

TEST_CASE("part 3 renders of every project scene have no NaN, infinite or negative radiance",
          "[part3][direct][sanity]") {
  int scenes = 0;
  for (const std::string& name : list_dir(PT_PROJECT_SCENES)) {
    if (name.size() < 4 || name.substr(name.size() - 4) != ".dae") continue;
    ++scenes;
    Scene scene = load_collada(project_scene(name));
    fit_course_view(scene.camera, 32, 24);
    for (bool hemisphere : {false, true}) {
      RenderOptions o = render_options(3, 32, 24, 4, 2, 71);
      o.hemisphere_sampling = hemisphere;
      const RenderResult r = render_scene(scene, o);
      int bad = 0;
      for (const Color& c : r.image.pixels) bad += valid_radiance(c) ? 0 : 1;
      INFO(name << (hemisphere ? " -H" : " light sampling") << ": " << bad << " bad pixels");
      CHECK(bad == 0);
    }
  }
  CHECK(scenes >= 5);
}
