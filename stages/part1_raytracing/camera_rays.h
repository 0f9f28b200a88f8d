// Part 1, task 1: camera rays.
#pragma once
#include "common/camera.h"
#include "common/ray.h"

namespace pt {

// The camera ray through the normalised image point (x, y): (0, 0) is the
// bottom-left corner of the image and (1, 1) the top-right.
// Contract: origin at the camera position; direction through the point
// ((2x-1) tan(hFov/2), (2y-1) tan(vFov/2), -1) of the camera-space sensor,
// turned into world space and normalised; min_t = near_clip, max_t = far_clip.
Ray generate_ray(const Camera& cam, double x, double y);

}  // namespace pt
