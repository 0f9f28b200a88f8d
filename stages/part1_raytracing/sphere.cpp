#include "stages/part1_raytracing/sphere.h"

#include <cmath>
#include <limits>

#include "common/todo.h"

namespace pt {

bool intersect_sphere(const Sphere& s, Ray& r, Hit* hit) {
  // BEGIN SOLUTION
  // STUB: PT_TODO(1, "no sphere is ever hit");
  // STUB: unused(s, r, hit);
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
  if (!(t <= double(std::numeric_limits<float>::max()))) return false;  // beyond what a float t can hold
  r.max_t = float(t);
  if (hit) {
    hit->t = float(t);
    const Vec3 outward = r.at(float(t)) - s.center;
    const float length = norm(outward);
    if (length > 0.0f && std::isfinite(length)) {
      hit->n = normalize(outward);
    } else {
      // Its squared length overflowed (a radius past ~1e19) or the hit
      // point lost every digit (a ray from ~1e38 away): in double it is
      // exact enough, and facing the ray is all that is left when even
      // that cancels to zero.
      const Vec3d v = oc + d * t;
      const double lv = norm(v);
      hit->n = lv > 0.0 && std::isfinite(lv) ? Vec3(v / lv) : normalize(-r.d);
    }
    hit->material = s.material;
  }
  return true;
  // END SOLUTION
}

}  // namespace pt
