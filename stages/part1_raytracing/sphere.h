// Part 1, task 4: ray-sphere intersection.
#pragma once
#include "common/ray.h"
#include "common/scene.h"

namespace pt {

// Tests `r` against sphere `s`.
// Contract: the hit is the nearer root of |o + t d - c|^2 = R^2 that lies in
// [r.min_t, r.max_t] (so a ray starting inside the sphere hits the far
// side). On a hit: r.max_t = t, and when `hit` is not null it receives t,
// the outward unit normal (p - c) / R and the sphere's material.
bool intersect_sphere(const Sphere& s, Ray& r, Hit* hit);

}  // namespace pt
