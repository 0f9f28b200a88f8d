#include "stages/part1_raytracing/triangle.h"

#include <cmath>

#include "common/todo.h"

namespace pt {

bool intersect_triangle(const Triangle& tri, Ray& r, Hit* hit) {
  // BEGIN SOLUTION
  // STUB: PT_TODO(1, "no triangle is ever hit");
  // STUB: unused(tri, r, hit);
  // STUB: return false;
  const Vec3 e1 = tri.p2 - tri.p1, e2 = tri.p3 - tri.p1;
  const Vec3 s1 = cross(r.d, e2);
  const float det = dot(s1, e1);
  if (det == 0.0f || !std::isfinite(det)) return false;  // parallel (or degenerate)
  const float inv = 1.0f / det;
  const Vec3 s = r.o - tri.p1;
  const float b1 = dot(s1, s) * inv;
  if (b1 < 0.0f || b1 > 1.0f) return false;
  const Vec3 s2 = cross(s, e1);
  const float b2 = dot(s2, r.d) * inv;
  if (b2 < 0.0f || b1 + b2 > 1.0f) return false;
  const float t = dot(s2, e2) * inv;
  if (!(t >= r.min_t && t <= r.max_t)) return false;
  r.max_t = t;
  if (hit) {
    hit->t = t;
    hit->n = normalize(tri.n1 * (1.0f - b1 - b2) + tri.n2 * b1 + tri.n3 * b2);
    hit->material = tri.material;
  }
  return true;
  // END SOLUTION
}

}  // namespace pt
