// Part 1 rendering: normal shading through the brute-force intersector,
// pixel sampling, exact counters, cell renders, thread-count determinism.
#include <catch2/catch.hpp>
#include <cstring>

#include "stages/part1_raytracing/brute_force.h"
#include "stages/part1_raytracing/pixel_sampling.h"
#include "stages/part1_raytracing/camera_rays.h"
#include "pathtracer/render_job.h"
#include "stages/part1_raytracing/shading.h"

using namespace pt;

namespace {

// A quad facing +Z at z = 0 filling x, y in [-1, 1], a sphere in front of
// it, seen from z = 3.
Scene small_scene() {
  Scene s;
  s.materials.push_back(Material{});
  Triangle a, b;
  a.p1 = {-1, -1, 0}; a.p2 = {1, -1, 0}; a.p3 = {1, 1, 0};
  b.p1 = {-1, -1, 0}; b.p2 = {1, 1, 0}; b.p3 = {-1, 1, 0};
  a.n1 = a.n2 = a.n3 = b.n1 = b.n2 = b.n3 = {0, 0, 1};
  s.triangles = {a, b};
  s.spheres.push_back(Sphere{{0.3f, 0.2f, 0.5f}, 0.3f, 0});
  s.camera.hfov_deg = 60;
  s.camera.vfov_deg = 45;
  s.camera.look_at(Vec3d(0, 0, 3), Vec3d(0, 0, 0), Vec3d(0, 1, 0));
  return s;
}

RenderOptions options(int w, int h, int spp, int threads) {
  RenderOptions o;
  o.width = w;
  o.height = h;
  o.samples_per_pixel = spp;
  o.threads = threads;
  o.progress = false;
  o.part = 1;  // brute force: every primitive tested
  return o;
}

}  // namespace

TEST_CASE("normal shading is n/2 + 1/2 on hits and black on misses", "[part1][render]") {
  Scene s = small_scene();
  BruteForceIntersector isect(s);
  // Straight at the quad away from the sphere: n = +Z.
  const Color quad = normal_shading(isect, Ray({-0.5f, -0.5f, 3}, {0, 0, -1}));
  CHECK(quad.x == Approx(0.5f));
  CHECK(quad.y == Approx(0.5f));
  CHECK(quad.z == Approx(1.0f));
  const Color sky = normal_shading(isect, Ray({5, 5, 3}, {0, 0, -1}));
  CHECK(sky == Color(0.0f));
  // The sphere is in front of the quad: its top point has n = +Y.
  const Color top = normal_shading(isect, Ray({0.3f, 0.2f + 0.3f, 3}, {0, 0, -1}, 0.0f, 100.0f));
  CHECK(top.y == Approx(1.0f).margin(1e-2));
}

TEST_CASE("the brute-force intersector counts every query and primitive test exactly", "[part1][render]") {
  Scene s = small_scene();
  configure_camera(s.camera, options(16, 12, 3, 1));
  const RenderResult r = render_scene(s, options(16, 12, 3, 2));
  CHECK(r.stats.closest_queries == 16u * 12u * 3u);
  CHECK(r.stats.shadow_queries == 0u);
  CHECK(r.stats.primitive_tests == 16u * 12u * 3u * 3u);
  for (uint32_t n : r.image.samples) CHECK(n == 3u);
}

TEST_CASE("the same seed gives a bit-identical image for 1 and 2 threads", "[part1][render][determinism]") {
  Scene s = small_scene();
  configure_camera(s.camera, options(40, 30, 4, 1));
  const RenderResult one = render_scene(s, options(40, 30, 4, 1));
  const RenderResult two = render_scene(s, options(40, 30, 4, 2));
  REQUIRE(one.image.pixels.size() == two.image.pixels.size());
  CHECK(std::memcmp(one.image.pixels.data(), two.image.pixels.data(), one.image.pixels.size() * sizeof(Color)) == 0);
  // A different seed changes the jittered samples, hence the image.
  RenderOptions other = options(40, 30, 4, 2);
  other.seed = 99;
  const RenderResult reseeded = render_scene(s, other);
  CHECK(std::memcmp(one.image.pixels.data(), reseeded.image.pixels.data(),
                    one.image.pixels.size() * sizeof(Color)) != 0);
}

TEST_CASE("one sample per pixel goes through the pixel centre, more are jittered inside it", "[part1][render]") {
  Scene s = small_scene();
  configure_camera(s.camera, options(8, 6, 1, 1));
  std::vector<Ray> seen;
  const RadianceFn record = [&](const Ray& r, Rng&) {
    seen.push_back(r);
    return Color(1.0f, 2.0f, 3.0f);
  };
  const Color c = raytrace_pixel(s.camera, 2, 3, 1, 0, record);
  REQUIRE(seen.size() == 1);
  CHECK(c == Color(1.0f, 2.0f, 3.0f));
  const Ray centre = generate_ray(s.camera, 2.5 / 8, 3.5 / 6);
  INFO("Hint: with one sample per pixel (-s 1) the ray goes through the pixel's centre, ((x + 0.5) / width, "
       "(y + 0.5) / height), with no jitter, as in the course; only -s 2 and more jitter it.");
  CHECK(seen[0].d.x == Approx(centre.d.x));
  CHECK(seen[0].d.y == Approx(centre.d.y));

  seen.clear();
  raytrace_pixel(s.camera, 2, 3, 64, 0, record);
  REQUIRE(seen.size() == 64);
  const Ray lo = generate_ray(s.camera, 2.0 / 8, 3.0 / 6), hi = generate_ray(s.camera, 3.0 / 8, 4.0 / 6);
  int distinct = 0;
  for (const Ray& r : seen) {
    // Inside the pixel's footprint (directions are monotone in x and y here).
    CHECK(r.d.x / -r.d.z >= lo.d.x / -lo.d.z - 1e-6f);
    CHECK(r.d.x / -r.d.z <= hi.d.x / -hi.d.z + 1e-6f);
    CHECK(r.d.y / -r.d.z >= lo.d.y / -lo.d.z - 1e-6f);
    CHECK(r.d.y / -r.d.z <= hi.d.y / -hi.d.z + 1e-6f);
    distinct += (r.d.x != centre.d.x);
  }
  CHECK(distinct == 64);
}

TEST_CASE("the average over samples is returned, not the sum", "[part1][render]") {
  Scene s = small_scene();
  configure_camera(s.camera, options(8, 6, 1, 1));
  int calls = 0;
  const RadianceFn alternating = [&](const Ray&, Rng&) { return Color(float(calls++ % 2)); };
  const Color c = raytrace_pixel(s.camera, 0, 0, 10, 0, alternating);
  CHECK(c.x == Approx(0.5f));
}

TEST_CASE("a cell render (-p) fills only the cell", "[part1][render]") {
  Scene s = small_scene();
  RenderOptions o = options(20, 10, 1, 2);
  o.cell_set = true;
  o.cell_x = 4;
  o.cell_y = 2;
  o.cell_w = 5;
  o.cell_h = 3;
  configure_camera(s.camera, o);
  const RenderResult r = render_scene(s, o);
  const RenderResult full = render_scene(s, options(20, 10, 1, 1));
  int inside = 0;
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 20; ++x) {
      const bool in = x >= 4 && x < 9 && y >= 2 && y < 5;
      CHECK(r.image.samples[r.image.index(x, y)] == (in ? 1u : 0u));
      if (in) {
        CHECK(r.image.at(x, y) == full.image.at(x, y));
        ++inside;
      } else {
        CHECK(r.image.at(x, y) == Color(0.0f));
      }
    }
  CHECK(inside == 15);
  CHECK(r.stats.closest_queries == 15u);
}
