// Part 2, task 2: does a ray's interval meet a box?
#pragma once
#include "common/todo.h"
#include "common/vec3.h"

namespace pt {

// Slab test of the ray o + t d, t in [t_min, t_max], against the box
// [lo, hi], given inv_d = (1/d.x, 1/d.y, 1/d.z) (infinite for zero
// components). Contract: returns whether some t in [t_min, t_max] lies in
// the box, and sets *t_enter to the first such t.
inline bool slab_test(const Vec3& lo, const Vec3& hi, const Vec3& o, const Vec3& inv_d, float t_min, float t_max,
                      float* t_enter) {
  // BEGIN SOLUTION
  // STUB: unused(lo, hi, o, inv_d, t_max);
  // STUB: *t_enter = t_min;  // every box is "hit": correct, but no faster than testing everything
  // STUB: return true;
  // Per axis, the ray is inside the slab between the two plane crossings.
  // The comparisons are written so that a NaN (0 * inf, a ray lying in a
  // slab plane) leaves the interval unchanged instead of poisoning it.
  for (int a = 0; a < 3; ++a) {
    float t0 = (lo[a] - o[a]) * inv_d[a];
    float t1 = (hi[a] - o[a]) * inv_d[a];
    if (t0 > t1) {
      const float s = t0;
      t0 = t1;
      t1 = s;
    }
    t_min = t0 > t_min ? t0 : t_min;
    t_max = t1 < t_max ? t1 : t_max;
  }
  *t_enter = t_min;
  return t_min <= t_max;
  // END SOLUTION
}

}  // namespace pt
