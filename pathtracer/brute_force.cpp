#include "brute_force.h"

#include "sphere.h"
#include "stats.h"
#include "triangle.h"

namespace pt {

bool BruteForceIntersector::intersect(Ray& r, Hit* hit) const {
  RayStats& stats = thread_ray_stats();
  ++stats.closest_queries;
  stats.primitive_tests += scene_.num_primitives();
  bool found = false;
  const int nt = int(scene_.triangles.size());
  for (int i = 0; i < nt; ++i)
    if (intersect_triangle(scene_.triangles[i], r, hit)) {
      found = true;
      if (hit) hit->primitive = i;
    }
  for (int i = 0; i < int(scene_.spheres.size()); ++i)
    if (intersect_sphere(scene_.spheres[i], r, hit)) {
      found = true;
      if (hit) hit->primitive = nt + i;
    }
  return found;
}

bool BruteForceIntersector::occluded(const Ray& ray) const {
  RayStats& stats = thread_ray_stats();
  ++stats.shadow_queries;
  Ray r = ray;
  for (const Triangle& t : scene_.triangles) {
    ++stats.primitive_tests;
    if (intersect_triangle(t, r, nullptr)) return true;
  }
  for (const Sphere& s : scene_.spheres) {
    ++stats.primitive_tests;
    if (intersect_sphere(s, r, nullptr)) return true;
  }
  return false;
}

}  // namespace pt
