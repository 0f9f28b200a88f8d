#include "camera_rays.h"

#include <cmath>

#include "todo.h"

namespace pt {

Ray generate_ray(const Camera& cam, double x, double y) {
  // BEGIN SOLUTION
  // STUB: todo_once("Part 1: generate_ray (stages/part1_raytracing/camera_rays.cpp)");
  // STUB: (void)x; (void)y;
  // STUB: return Ray(Vec3(cam.position), Vec3(0, 0, -1), float(cam.near_clip), float(cam.far_clip));
  const double deg = 3.14159265358979323846 / 180.0;
  const double tan_h = std::tan(0.5 * cam.hfov_deg * deg);
  const double tan_v = std::tan(0.5 * cam.vfov_deg * deg);
#ifdef PT_MUTANT_camera_y_flipped
  const Vec3d sensor((2.0 * x - 1.0) * tan_h, (1.0 - 2.0 * y) * tan_v, -1.0);  // upside down
#else
  const Vec3d sensor((2.0 * x - 1.0) * tan_h, (2.0 * y - 1.0) * tan_v, -1.0);
#endif
#ifdef PT_MUTANT_camera_not_normalized
  const Vec3d dir = cam.to_world(sensor);  // not normalised
#else
  const Vec3d dir = normalize(cam.to_world(sensor));
#endif
  return Ray(Vec3(cam.position), Vec3(dir), float(cam.near_clip), float(cam.far_clip));
  // END SOLUTION
}

}  // namespace pt
