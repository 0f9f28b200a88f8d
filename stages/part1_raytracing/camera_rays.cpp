#include "stages/part1_raytracing/camera_rays.h"

#include <cmath>

#include "common/math_constants.h"
#include "common/todo.h"

namespace pt {

Ray generate_ray(const Camera& cam, double x, double y) {
  // BEGIN SOLUTION
  // STUB: PT_TODO(1, "every camera ray points straight down -z from the camera");
  // STUB: unused(x, y);
  // STUB: return Ray(Vec3(cam.position), Vec3(0, 0, -1), float(cam.near_clip), float(cam.far_clip));
  const double deg = kPiDouble / 180.0;
  const double tan_h = std::tan(0.5 * cam.hfov_deg * deg);
  const double tan_v = std::tan(0.5 * cam.vfov_deg * deg);
  const Vec3d sensor((2.0 * x - 1.0) * tan_h, (2.0 * y - 1.0) * tan_v, -1.0);
  const Vec3d dir = normalize(cam.to_world(sensor));
  return Ray(Vec3(cam.position), Vec3(dir), float(cam.near_clip), float(cam.far_clip));
  // END SOLUTION
}

}  // namespace pt
