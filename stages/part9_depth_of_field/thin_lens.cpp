#include "stages/part9_depth_of_field/thin_lens.h"

#include <cmath>

#include "common/math_constants.h"
#include "common/todo.h"
#include "stages/part1_raytracing/camera_rays.h"

namespace pt {

Ray generate_ray_for_thin_lens(const Camera& cam, double x, double y, double u1, double u2) {
  // BEGIN SOLUTION
  // STUB: PT_TODO(9, "a pinhole: -b has no effect");
  // STUB: unused(u1, u2);
  // STUB: return generate_ray(cam, x, y);
  const double deg = kPiDouble / 180.0;
  const double sx = (2 * x - 1) * std::tan(0.5 * cam.hfov_deg * deg);
  const double sy = (2 * y - 1) * std::tan(0.5 * cam.vfov_deg * deg);
  // The sensor point at z = -1 scaled onto the plane of focus.
  const Vec3d focus = Vec3d(sx, sy, -1.0) * cam.focal_distance;
  const double r = cam.lens_radius * std::sqrt(u1), phi = 2 * kPiDouble * u2;
  const Vec3d lens(r * std::cos(phi), r * std::sin(phi), 0.0);
  const Vec3d d = normalize(cam.to_world(focus - lens));
  return Ray(Vec3(cam.position + cam.to_world(lens)), Vec3(d), float(cam.near_clip), float(cam.far_clip));
  // END SOLUTION
}

}  // namespace pt
