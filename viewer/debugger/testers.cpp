// The intersection tester and the light-sample tester.
#include <cmath>

#include "viewer/debugger/debugger.h"
#include "stages/part3_direct_lighting/direct_lighting.h"
#include "viewer/debugger/json_values.h"
#include "viewer/debugger/todo_collector.h"
#include "common/path_recorder.h"
#include "common/rng.h"
#include "stages/part1_raytracing/sphere.h"
#include "stages/part1_raytracing/triangle.h"

namespace pt::debug {

namespace {

bool finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

void check_point(const Vec3& v, const char* what) {
  if (!finite(v)) throw InputError(std::string(what) + " must be three finite numbers");
}

void check_direction(const Vec3& v, const char* what) {
  check_point(v, what);
  if (!(norm2(v) > 0) || !std::isfinite(norm2(v)))
    throw InputError(std::string(what) + " must be a non-zero vector whose squared length is finite");
}

Ray checked_ray(const RayInput& in) {
  check_point(in.origin, "the ray's origin");
  check_direction(in.direction, "the ray's direction");
  if (std::isnan(in.min_t) || std::isnan(in.max_t)) throw InputError("min_t and max_t must be numbers, not NaN");
  if (in.min_t > in.max_t) throw InputError("min_t must not exceed max_t");
  return Ray(in.origin, in.direction, in.min_t, in.max_t);
}

// Calls `test` (an intersect_* function) and fills the result.
template <class Shape>
IntersectionResult run_test(const char* function, bool (*test)(const Shape&, Ray&, Hit*), const Shape& shape,
                            const Ray& ray) {
  IntersectionResult res;
  res.function = function;
  res.ray = ray;
  TodoCollector todos;
  {
    ScopedPathRecorder install(&todos);
    Ray r = ray;
    Hit h;
    try {
      res.hit = test(shape, r, &h);
    } catch (const std::exception& e) {
      res.error = std::string(function) + ": " + e.what();
    } catch (...) {
      res.error = std::string(function) + ": threw something that is not a std::exception";
    }
    res.max_t_after = r.max_t;
    if (res.hit && res.ok()) {
      res.t = h.t;
      res.point = ray.at(h.t);
      res.normal = h.n;
      res.material = h.material;
    }
  }
  res.todos = todos.todos;
  return res;
}

}  // namespace

IntersectionResult test_ray_triangle(const Triangle& tri, const RayInput& ray) {
  const Ray r = checked_ray(ray);
  for (const Vec3* p : {&tri.p1, &tri.p2, &tri.p3}) check_point(*p, "every triangle vertex");
  for (const Vec3* n : {&tri.n1, &tri.n2, &tri.n3}) check_point(*n, "every triangle vertex normal");
  return run_test<Triangle>("intersect_triangle", &intersect_triangle, tri, r);
}

IntersectionResult test_ray_sphere(const Sphere& sphere, const RayInput& ray) {
  const Ray r = checked_ray(ray);
  check_point(sphere.center, "the sphere's centre");
  if (!(sphere.radius > 0) || !std::isfinite(sphere.radius))
    throw InputError("the sphere's radius must be a positive finite number");
  return run_test<Sphere>("intersect_sphere", &intersect_sphere, sphere, r);
}

IntersectionResult test_ray_primitive(const Scene& scene, int primitive, const RayInput& ray) {
  const long long n = (long long)scene.num_primitives();
  if (primitive < 0 || primitive >= n)
    throw InputError("primitive " + std::to_string(primitive) + " is out of range: the scene has " +
                     std::to_string(n) + " (0 to " + std::to_string(n - 1) + ")");
  const size_t i = size_t(primitive);
  if (i < scene.triangles.size()) return test_ray_triangle(scene.triangles[i], ray);
  return test_ray_sphere(scene.spheres[i - scene.triangles.size()], ray);
}

LightSamplesResult sample_light_many(const Scene& scene, int light_index, const Vec3& point, const Vec3& normal,
                                     int n, uint64_t seed, const Intersector* geometry) {
  if (light_index < 0 || size_t(light_index) >= scene.lights.size())
    throw InputError("light " + std::to_string(light_index) + " is out of range: the scene has " +
                     std::to_string(scene.lights.size()) + " light(s)");
  check_point(point, "the point");
  check_direction(normal, "the normal");
  if (n < 1 || n > kMaxLightSamples)
    throw InputError("the number of samples must be from 1 to " + std::to_string(kMaxLightSamples));
  const Light& light = scene.lights[size_t(light_index)];
  LightSamplesResult res;
  res.light = light_index;
  res.light_type = to_string(light.type);
  res.point = point;
  res.normal = normalize(normal);
  res.seed = seed;
  res.samples.reserve(size_t(n));
  TodoCollector todos;
  {
    ScopedPathRecorder install(&todos);
    Rng rng(seed);
    try {
      for (int i = 0; i < n; ++i) {
        LightSampleTest t;
        t.u1 = rng.uniform();
        t.u2 = rng.uniform();
        t.sample = sample_light(light, point, t.u1, t.u2);
        t.cos_theta = dot(res.normal, t.sample.wi);
        const float max_t = std::isfinite(t.sample.distance) ? t.sample.distance - kRayEpsilon : kInfinity;
        if (geometry && !is_black(t.sample.radiance) && t.cos_theta > 0 && max_t > kRayEpsilon) {
          t.shadow_tested = true;
          t.shadow_ray = Ray(point, t.sample.wi, kRayEpsilon, max_t);
          t.blocked = geometry->occluded(t.shadow_ray);
        }
        res.samples.push_back(t);
      }
    } catch (const std::exception& e) {
      res.error = std::string(geometry ? "sample_light or the occlusion query" : "sample_light") + ": " + e.what();
    }
  }
  res.todos = todos.todos;
  return res;
}

Json IntersectionResult::json() const {
  Json o = json_object();
  o.set("function", json_text(function)).set("ray", json_ray(ray)).set("hit", json_bool(hit));
  if (hit)
    o.set("t", json_float(t)).set("point", json_vec(point)).set("normal", json_vec(normal)).set("material",
                                                                                                 json_int(material));
  o.set("max_t_after", json_float(max_t_after)).set("todos", json_strings(todos));
  if (!error.empty()) o.set("error", json_text(error));
  return o;
}

// One line per sample: a call may take a million.
Json LightSampleTest::json() const {
  Json o = json_object(true);
  o.set("u", json_pair(u1, u2))
      .set("wi", json_vec(sample.wi))
      .set("distance", json_float(sample.distance))
      .set("pdf", json_float(sample.pdf))
      .set("radiance", json_vec(sample.radiance))
      .set("cos_theta", json_float(cos_theta))
      .set("shadow_tested", json_bool(shadow_tested));
  if (shadow_tested) o.set("shadow_ray", json_ray(shadow_ray)).set("blocked", json_bool(blocked));
  return o;
}

Json LightSamplesResult::json() const {
  std::vector<Json> items;
  items.reserve(samples.size());
  for (const LightSampleTest& s : samples) items.push_back(s.json());
  Json o = json_object();
  o.set("light", json_int(light))
      .set("light_type", json_text(light_type))
      .set("point", json_vec(point))
      .set("normal", json_vec(normal));
  o.set("seed", json_seed(seed)).set("samples", json_list(std::move(items))).set("todos", json_strings(todos));
  if (!error.empty()) o.set("error", json_text(error));
  return o;
}

}  // namespace pt::debug
