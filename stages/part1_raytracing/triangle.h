// Part 1, task 3: ray-triangle intersection.
#pragma once
#include "common/ray.h"
#include "common/scene.h"

namespace pt {

// Tests `r` against triangle `tri` (Moller-Trumbore).
// Contract: a hit is a t in [r.min_t, r.max_t] inside the triangle (edges
// included). On a hit: r.max_t = t, and when `hit` is not null it receives
// t, the unit normal interpolated from n1, n2, n3 with the barycentric
// coordinates, and the triangle's material. Returns whether it hit.
// Rays parallel to the triangle's plane miss.
bool intersect_triangle(const Triangle& tri, Ray& r, Hit* hit);

}  // namespace pt
