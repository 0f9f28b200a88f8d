// Axis-aligned bounding boxes.
#pragma once
#include <limits>

#include "common/vec3.h"

namespace pt {

struct BBox {
  Vec3 lo{std::numeric_limits<float>::infinity()};
  Vec3 hi{-std::numeric_limits<float>::infinity()};

  BBox() = default;
  BBox(const Vec3& a, const Vec3& b) : lo(vmin(a, b)), hi(vmax(a, b)) {}

  bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
  void expand(const Vec3& p) { lo = vmin(lo, p); hi = vmax(hi, p); }
  void expand(const BBox& b) { lo = vmin(lo, b.lo); hi = vmax(hi, b.hi); }
  Vec3 extent() const { return empty() ? Vec3(0.0f) : hi - lo; }
  Vec3 centroid() const { return (lo + hi) * 0.5f; }
  float surface_area() const {
    if (empty()) return 0.0f;
    const Vec3 e = hi - lo;
    return 2.0f * (e.x * e.y + e.y * e.z + e.z * e.x);
  }
  int longest_axis() const {
    const Vec3 e = extent();
    return (e.x >= e.y && e.x >= e.z) ? 0 : (e.y >= e.z ? 1 : 2);
  }
};

}  // namespace pt
