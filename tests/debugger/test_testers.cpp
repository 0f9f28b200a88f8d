// The intersection tester and the light-sample tester (viewer/debugger):
// they report exactly what the build's intersect_triangle / intersect_sphere
// and sample_light return, refuse absurd input with a one-line InputError,
// and write JSON the page can read (NaN and infinities as strings).
//
// Deliberate bug (planted in a scratch copy) -> tests here that failed on it:
//   the tester normalises the direction          -> agrees with intersect_* (t in units of d)
//   max_t_after read from the input ray          -> agrees with intersect_* (max_t after)
//   light samples drawn with another seed order   -> agrees with sample_light
//   shadow ray without the epsilon at the light   -> agrees with the occlusion query
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "stages/part2_bvh/bvh.h"
#include "common/collada.h"
#include "viewer/debugger/debugger.h"
#include "stages/part3_direct_lighting/direct_lighting.h"
#include "common/json.h"
#include "viewer/debugger/json_values.h"
#include "stages/part1_raytracing/sphere.h"
#include "tests/debugger/json_read.h"
#include "tests/support.h"
#include "stages/part1_raytracing/triangle.h"

using namespace pt;
using namespace pt::test;

namespace {

const float kNaN = std::numeric_limits<float>::quiet_NaN();

bool same(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool same(const Vec3& a, const Vec3& b) { return same(a.x, b.x) && same(a.y, b.y) && same(a.z, b.z); }

// `call` throws an InputError whose message is one line naming `mentions`.
template <typename Call>
void check_refused(Call call, const std::string& mentions) {
  try {
    call();
    FAIL("accepted");
  } catch (const debug::InputError& e) {
    const std::string m = e.what();
    INFO(m);
    CHECK(m.find('\n') == std::string::npos);
    CHECK(m.find(mentions) != std::string::npos);
  }
}

// A parsed value laid out on one line (objects and arrays), so that a whole
// result compares with one string.
Json on_one_line(Json v) {
  v.one_line = true;
  for (Json& item : v.array) item = on_one_line(item);
  for (auto& member : v.members) member.second = on_one_line(member.second);
  return v;
}

Triangle tilted_triangle() {
  Triangle t;
  t.p1 = {-1, -1, 0};
  t.p2 = {2, -1, 0.5f};
  t.p3 = {0, 2, -0.5f};
  t.n1 = normalize(Vec3(0, 0.2f, 1));
  t.n2 = normalize(Vec3(0.3f, 0, 1));
  t.n3 = normalize(Vec3(-0.2f, -0.1f, 1));
  t.material = 2;
  return t;
}

// Rays of every kind: hits inside, on an edge and a vertex, misses beside,
// parallel, behind, outside [min_t, max_t], unnormalised directions.
std::vector<debug::RayInput> ray_table() {
  std::vector<debug::RayInput> rays;
  const auto add = [&](Vec3 o, Vec3 d, float min_t, float max_t) { rays.push_back({o, d, min_t, max_t}); };
  const float inf = kInfinity;
  add({0, 0, 5}, {0, 0, -1}, 0, inf);
  add({0.2f, 0.3f, 5}, {0, 0, -2}, 0, inf);        // not unit: t in units of d
  add({0, 0, -5}, {0, 0, 1}, 0, inf);              // from behind
  add({0, 0, 5}, {0, 0, -1}, 0, 4.0f);             // the hit is beyond max_t
  add({0, 0, 5}, {0, 0, -1}, 6.0f, inf);           // before min_t
  add({0, 0, 5}, {0, 0, -1}, 0, 0);                // empty interval at 0
  add({5, 5, 5}, {0, 0, -1}, 0, inf);              // beside
  add({-1, -1, 5}, {0, 0, -1}, 0, inf);            // a vertex
  add({0.5f, -1, 5}, {0, 0, -1}, 0, inf);          // an edge
  add({0, 0, 0.1f}, {1, 0, 0}, 0, inf);            // parallel to z = 0
  add({0, 0, 5}, {0, 0, 1}, 0, inf);               // pointing away
  add({3, 1, 4}, {-0.5f, -0.2f, -0.8f}, 0, inf);   // oblique
  add({0.3f, 0.1f, 0}, {0.1f, 0.2f, 1}, 0, inf);   // starting on the plane
  add({0, 0, 0}, {0, 0, -1}, 0.5f, 10.0f);         // from inside the sphere
  add({0, 0, 0}, {1e-20f, 0, 0}, 0, inf);          // tiny but non-zero
  add({0, 0, 1e6f}, {0, 0, -1}, 0, inf);           // far away
  return rays;
}

// Runs the table's rays through the build's own function `direct` and
// through the tester `tester` on the same shape: the same verdict, max_t
// after the call, and on a hit the same t and normal (plus `on_hit`'s
// checks). Returns how many rays hit.
template <class Shape, class Direct, class Tester, class OnHit>
int count_agreeing_hits(const char* function, Direct direct, Tester tester, const Shape& shape, OnHit on_hit) {
  int hits = 0;
  for (const debug::RayInput& in : ray_table()) {
    Ray r(in.origin, in.direction, in.min_t, in.max_t);
    Hit h;
    const bool hit = direct(shape, r, &h);
    const debug::IntersectionResult res = tester(shape, in);
    INFO(res.to_json());
    REQUIRE(res.ok());
    CHECK(res.function == function);
    CHECK(res.hit == hit);
    CHECK(same(res.max_t_after, r.max_t));
    if (hit) {
      ++hits;
      CHECK(same(res.t, h.t));
      CHECK(same(res.normal, h.n));
      on_hit(res, in, h);
    }
  }
  return hits;
}

}  // namespace

TEST_CASE("the intersection tester agrees with intersect_triangle on a table of rays", "[debugger][part1]") {
  const Triangle tri = tilted_triangle();
  const int hits = count_agreeing_hits("intersect_triangle", intersect_triangle, debug::test_ray_triangle, tri,
                                       [](const debug::IntersectionResult& res, const debug::RayInput& in,
                                          const Hit& h) {
                                         CHECK(res.material == h.material);
                                         CHECK(same(res.point, Ray(in.origin, in.direction).at(h.t)));
                                       });
  CHECK(hits >= 5);
  // A hand-checked row: straight down onto z = 0 from z = 5 with |d| = 2.
  const debug::IntersectionResult down = debug::test_ray_triangle(tri, {{0.2f, 0.3f, 5}, {0, 0, -2}, 0, kInfinity});
  REQUIRE(down.hit);
  CHECK(down.t == Approx(2.5f - 0.0f).margin(0.1f));
  CHECK(down.material == 2);
}

TEST_CASE("the intersection tester agrees with intersect_sphere on a table of rays", "[debugger][part1]") {
  Sphere s;
  s.center = {0.1f, -0.2f, 0};
  s.radius = 1.5f;
  s.material = 4;
  const int hits = count_agreeing_hits(
      "intersect_sphere", intersect_sphere, debug::test_ray_sphere, s,
      [](const debug::IntersectionResult& res, const debug::RayInput&, const Hit&) { CHECK(res.material == 4); });
  CHECK(hits >= 5);
  const debug::IntersectionResult inside = debug::test_ray_sphere(s, {{0.1f, -0.2f, 0}, {0, 0, -1}, 0, kInfinity});
  REQUIRE(inside.hit);
  CHECK(inside.t == Approx(1.5f));  // from the centre: the far side
}

TEST_CASE("a primitive picked in the scene is tested as the scene stores it", "[debugger]") {
  Scene scene = load_collada(project_scene("CBspheres_lambertian.dae"));
  REQUIRE(!scene.spheres.empty());
  const int n = int(scene.num_primitives());
  const int sphere_id = int(scene.triangles.size());
  const Sphere& sp = scene.spheres[0];
  const debug::RayInput at_sphere{sp.center + Vec3(0, 0, 5), {0, 0, -1}, 0, kInfinity};
  const debug::IntersectionResult picked = debug::test_ray_primitive(scene, sphere_id, at_sphere);
  CHECK(picked.function == "intersect_sphere");
  CHECK(picked.hit);
  CHECK(picked.t == Approx(5.0f - sp.radius));
  CHECK(debug::test_ray_primitive(scene, 0, at_sphere).function == "intersect_triangle");
  CHECK_THROWS_AS(debug::test_ray_primitive(scene, n, at_sphere), debug::InputError);
  CHECK_THROWS_AS(debug::test_ray_primitive(scene, -1, at_sphere), debug::InputError);
}

TEST_CASE("the intersection tester refuses absurd rays and shapes with a one-line InputError", "[debugger]") {
  const Triangle tri = tilted_triangle();
  Sphere s;
  s.radius = 1;
  const auto refused = [&](const debug::RayInput& in, const Sphere& sphere, const std::string& mentions) {
    for (int shape = 0; shape < 2; ++shape) {
      INFO("expecting a message about " << mentions << (shape ? " (sphere)" : " (triangle)"));
      check_refused([&] {
        if (shape)
          debug::test_ray_sphere(sphere, in);
        else
          debug::test_ray_triangle(tri, in);
      }, mentions);
    }
  };
  const Vec3 o(0, 0, 5), d(0, 0, -1);
  refused({o, Vec3(0.0f), 0, kInfinity}, s, "direction");
  refused({o, Vec3(kNaN, 0, -1), 0, kInfinity}, s, "direction");
  refused({o, Vec3(0, kInfinity, -1), 0, kInfinity}, s, "direction");
  refused({o, Vec3(3e20f, 3e20f, 0), 0, kInfinity}, s, "direction");  // its squared length overflows
  refused({Vec3(kNaN, 0, 0), d, 0, kInfinity}, s, "origin");
  refused({o, d, 2, 1}, s, "min_t");
  refused({o, d, kNaN, 1}, s, "NaN");
  refused({o, d, 0, kNaN}, s, "NaN");
  for (float r : {-1.0f, 0.0f, kNaN, kInfinity}) {
    Sphere bad = s;
    bad.radius = r;
    INFO("radius " << r);
    CHECK_THROWS_AS(debug::test_ray_sphere(bad, {o, d, 0, kInfinity}), debug::InputError);
  }
  Triangle bad = tri;
  bad.p2.y = kNaN;
  CHECK_THROWS_AS(debug::test_ray_triangle(bad, {o, d, 0, kInfinity}), debug::InputError);
}

TEST_CASE("the light-sample tester reports what sample_light returns and the estimator's shadow rays",
          "[debugger][part3]") {
  Scene scene = load_collada(project_scene("CBlights.dae"));
  const BVH bvh(scene);
  const Vec3 p(0.1f, 0.02f, 0.1f), n(0, 1, 0);  // just above the floor
  int blocked = 0, lit = 0;
  for (size_t li = 0; li < scene.lights.size(); ++li) {
    const debug::LightSamplesResult res = debug::sample_light_many(scene, int(li), p, n * 3.0f, 200, 17, &bvh);
    REQUIRE(res.ok());
    REQUIRE(res.samples.size() == 200);
    CHECK(res.light_type == to_string(scene.lights[li].type));
    CHECK(same(res.normal, n));
    Rng rng(17);
    for (const debug::LightSampleTest& t : res.samples) {
      const float u1 = rng.uniform(), u2 = rng.uniform();
      const LightSample s = sample_light(scene.lights[li], p, u1, u2);
      CHECK(same(t.u1, u1));
      CHECK(same(t.u2, u2));
      CHECK(same(t.sample.wi, s.wi));
      CHECK(same(t.sample.pdf, s.pdf));
      CHECK(same(t.sample.distance, s.distance));
      CHECK(same(t.sample.radiance, s.radiance));
      CHECK(t.cos_theta == Approx(s.wi.y));
      if (!t.shadow_tested) continue;
      const Ray shadow(p, s.wi, kRayEpsilon, s.distance - kRayEpsilon);
      CHECK(same(t.shadow_ray.max_t, shadow.max_t));
      CHECK(t.blocked == bvh.occluded(shadow));
      (t.blocked ? blocked : lit)++;
    }
  }
  CHECK(lit > 0);
  CHECK(blocked > 0);  // the lights' backing plates and the spheres shadow some samples
  const debug::LightSamplesResult no_geometry = debug::sample_light_many(scene, 0, p, n, 3, 1);
  for (const debug::LightSampleTest& t : no_geometry.samples) CHECK(!t.shadow_tested);
}

TEST_CASE("the light-sample tester refuses absurd input with a one-line InputError", "[debugger]") {
  Scene scene = load_collada(project_scene("CBlights.dae"));
  const int lights = int(scene.lights.size());
  const Vec3 p(0, 0.5f, 0), n(0, 1, 0);
  const auto refused = [&](int light, const Vec3& point, const Vec3& normal, int count, const std::string& mentions) {
    INFO("expecting a message about " << mentions);
    check_refused([&] { debug::sample_light_many(scene, light, point, normal, count, 1); }, mentions);
  };
  refused(lights, p, n, 4, "light " + std::to_string(lights));
  refused(-1, p, n, 4, "light -1");
  refused(0, Vec3(kNaN, 0, 0), n, 4, "point");
  refused(0, p, Vec3(0.0f), 4, "normal");
  refused(0, p, n, 0, "number of samples");
  refused(0, p, n, debug::kMaxLightSamples + 1, "number of samples");
}

TEST_CASE("JSON: numbers read back as the same float, NaN and infinities become strings", "[debugger]") {
  CHECK(write_json(debug::json_float(0.1f)) == "0.100000001\n");
  CHECK(std::stof(write_json(debug::json_float(0.1f))) == 0.1f);
  CHECK(write_json(debug::json_float(kNaN)) == "\"nan\"\n");
  CHECK(write_json(debug::json_float(kInfinity)) == "\"inf\"\n");
  CHECK(write_json(debug::json_float(-kInfinity)) == "\"-inf\"\n");
  for (float v : {0.1f, 1.0f / 3.0f, -2.5e-30f, 3.4028235e38f, 1e-45f, kNaN, kInfinity, -kInfinity}) {
    INFO(v);
    const Json back = parse_json(write_json(debug::json_float(v)), "a float");
    CHECK(same(read_float(&back), v));
  }
  CHECK(write_json(debug::json_seed(18446744073709551615ull)) == "\"18446744073709551615\"\n");

  // Strings are escaped.
  debug::IntersectionResult quoted;
  quoted.function = "a\"b";
  quoted.error = "x\ny";
  const Json q = parse_json(quoted.to_json(), "a result with quotes");
  CHECK(q.str("function") == "a\"b");
  CHECK(q.str("error") == "x\ny");

  // Every member of a miss, in order (laid out on one line to compare).
  const debug::IntersectionResult miss =
      debug::test_ray_triangle(tilted_triangle(), {{5, 5, 5}, {0, 0, -1}, 0, kInfinity});
  CHECK(write_json(on_one_line(parse_json(miss.to_json(), "a miss"))) ==
        "{\"function\": \"intersect_triangle\", \"ray\": {\"origin\": [5, 5, 5], \"direction\": [0, 0, -1], "
        "\"min_t\": 0, \"max_t\": \"inf\", \"depth\": 0}, \"hit\": false, \"max_t_after\": \"inf\", \"todos\": []}\n");

  // A hit's figures read back bit for bit.
  const debug::IntersectionResult hit =
      debug::test_ray_triangle(tilted_triangle(), {{0.2f, 0.3f, 5}, {0.01f, -0.003f, -2}, 0, kInfinity});
  REQUIRE(hit.hit);
  const Json h = parse_json(hit.to_json(), "a hit");
  CHECK(h.flag("hit"));
  CHECK(same(read_float(h.get("t")), hit.t));
  CHECK(same(read_float(h.get("max_t_after")), hit.max_t_after));
  CHECK(same(read_vec(h.get("point")), hit.point));
  CHECK(same(read_vec(h.get("normal")), hit.normal));
  CHECK(h.num("material", -1) == hit.material);
  REQUIRE(h.get("ray") != nullptr);
  CHECK(same(read_vec(h.get("ray")->get("direction")), hit.ray.d));

  // A light-sample test: the seed as a string, every sample's numbers.
  const Scene scene = load_collada(project_scene("CBlights.dae"));
  const BVH bvh(scene);
  const uint64_t seed = 0xfedcba9876543210ull;
  const debug::LightSamplesResult res =
      debug::sample_light_many(scene, 0, {0.1f, 0.02f, 0.1f}, {0, 1, 0}, 20, seed, &bvh);
  REQUIRE(res.ok());
  const Json l = parse_json(res.to_json(), "light samples");
  CHECK(l.str("seed") == std::to_string(seed));
  CHECK(l.str("light_type") == res.light_type);
  const Json* samples = l.get("samples");
  REQUIRE(samples != nullptr);
  REQUIRE(samples->array.size() == res.samples.size());
  for (size_t i = 0; i < res.samples.size(); ++i) {
    const Json& s = samples->array[i];
    const debug::LightSampleTest& t = res.samples[i];
    INFO("sample " << i);
    REQUIRE(s.get("u") != nullptr);
    REQUIRE(s.get("u")->array.size() == 2);
    CHECK(same(read_float(&s.get("u")->array[0]), t.u1));
    CHECK(same(read_float(&s.get("u")->array[1]), t.u2));
    CHECK(same(read_vec(s.get("wi")), t.sample.wi));
    CHECK(same(read_float(s.get("pdf")), t.sample.pdf));
    CHECK(same(read_float(s.get("distance")), t.sample.distance));
    CHECK(s.flag("shadow_tested") == t.shadow_tested);
    if (t.shadow_tested) {
      CHECK(s.flag("blocked") == t.blocked);
      REQUIRE(s.get("shadow_ray") != nullptr);
      CHECK(same(read_float(s.get("shadow_ray")->get("max_t")), t.shadow_ray.max_t));
    }
  }
}
