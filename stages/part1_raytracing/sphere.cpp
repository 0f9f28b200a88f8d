#include "sphere.h"

#include <cmath>

#include "todo.h"

namespace pt {

bool intersect_sphere(const Sphere& s, Ray& r, Hit* hit) {
  // BEGIN SOLUTION
  // STUB: todo_once("Part 1: intersect_sphere (stages/part1_raytracing/sphere.cpp)");
  // STUB: (void)s; (void)r; (void)hit;
  // STUB: return false;
  // Solve a t^2 + 2 b t + c = 0 with b = d.(o-c); in double, as the
  // difference of nearly equal terms loses float precision for far spheres.
  const Vec3d oc(r.o - s.center), d(r.d);
  const double a = dot(d, d), b = dot(oc, d);
  const double c = dot(oc, oc) - double(s.radius) * double(s.radius);
  const double disc = b * b - a * c;
  if (disc < 0.0 || a == 0.0) return false;
  const double root = std::sqrt(disc);
  // Numerically stable pair of roots (no cancellation in either).
  const double q = b > 0 ? -(b + root) : -(b - root);
  double t1 = q / a, t2 = q != 0.0 ? c / q : t1;
  if (t1 > t2) std::swap(t1, t2);
  double t;
  if (t1 >= r.min_t && t1 <= r.max_t)
    t = t1;
  else if (t2 >= r.min_t && t2 <= r.max_t)
    t = t2;
  else
    return false;
  r.max_t = float(t);
  if (hit) {
    hit->t = float(t);
    hit->n = normalize(r.at(float(t)) - s.center);
    hit->material = s.material;
  }
  return true;
  // END SOLUTION
}

}  // namespace pt
