// Part 9: depth of field: a thin lens instead of a pinhole.
#pragma once
#include "common/camera.h"
#include "common/ray.h"

namespace pt {

// The camera ray through the normalised image point (x, y) ((0, 0) the
// bottom-left corner, as for generate_ray) with lens sample (u1, u2) in
// [0, 1)^2. In camera space the lens is the disk of radius
// cam.lens_radius at the origin, in the plane z = 0; the plane of focus is
// z = -cam.focal_distance. The ray starts at the lens point
// (r cos phi, r sin phi, 0) with r = lens_radius sqrt(u1) and
// phi = 2 pi u2 (uniform over the disk), and passes through the point
// where the pinhole ray through (x, y) (generate_ray's direction
// ((2x-1) tan(hFov/2), (2y-1) tan(vFov/2), -1)) meets the plane of focus.
// Origin and direction turned into world space (the origin offset from
// cam.position), the direction normalised; min_t = near_clip,
// max_t = far_clip.
Ray generate_ray_for_thin_lens(const Camera& cam, double x, double y, double u1, double u2);

}  // namespace pt
