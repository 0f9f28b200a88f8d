#include "stages/part1_raytracing/brute_force.h"

#include "stages/part1_raytracing/sphere.h"
#include "common/stats.h"
#include "stages/part1_raytracing/triangle.h"

namespace pt {

bool intersect_every_primitive(const Scene& scene, Ray& r, Hit* hit) {
  thread_ray_stats().primitive_tests += scene.num_primitives();
  bool found = false;
  const int nt = int(scene.triangles.size());
  for (int i = 0; i < nt; ++i)
    if (intersect_triangle(scene.triangles[i], r, hit)) {
      found = true;
      if (hit) hit->primitive = i;
    }
  for (int i = 0; i < int(scene.spheres.size()); ++i)
    if (intersect_sphere(scene.spheres[i], r, hit)) {
      found = true;
      if (hit) hit->primitive = nt + i;
    }
  return found;
}

bool any_primitive_occludes(const Scene& scene, const Ray& ray) {
  RayStats& stats = thread_ray_stats();
  Ray r = ray;
  for (const Triangle& t : scene.triangles) {
    ++stats.primitive_tests;
    if (intersect_triangle(t, r, nullptr)) return true;
  }
  for (const Sphere& s : scene.spheres) {
    ++stats.primitive_tests;
    if (intersect_sphere(s, r, nullptr)) return true;
  }
  return false;
}

bool BruteForceIntersector::intersect(Ray& r, Hit* hit) const {
  ++thread_ray_stats().closest_queries;
  return intersect_every_primitive(scene_, r, hit);
}

bool BruteForceIntersector::occluded(const Ray& r) const {
  ++thread_ray_stats().shadow_queries;
  return any_primitive_occludes(scene_, r);
}

}  // namespace pt
