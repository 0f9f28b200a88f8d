#include "viewer/camera_file.h"

#include <cmath>
#include <cstdio>

namespace pt::viewer {

namespace {

std::string numbers(std::initializer_list<double> values) {
  std::string line;
  char buf[40];
  for (double v : values) {
    std::snprintf(buf, sizeof buf, "%.17g", v);
    if (!line.empty()) line += ' ';
    line += buf;
  }
  return line + "\n";
}

}  // namespace

std::string camera_settings_text(const Camera& cam) {
  // The course's orbit parameters: the direction from the target to the
  // camera in spherical angles about +Y, and the distance. The renderer
  // does not read them back; the course's GUI starts its orbit from them.
  const Vec3d v = cam.position - cam.target;
  const double r = norm(v);
  const double phi = r > 0 ? std::acos(std::fmax(-1.0, std::fmin(1.0, v.y / r))) : 0.0;
  const double theta = std::atan2(v.x, v.z);
  const Vec3d& x = cam.axis_x;
  const Vec3d& y = cam.axis_y;
  const Vec3d& z = cam.axis_z;
  return numbers({cam.hfov_deg, cam.vfov_deg, double(cam.width) / double(cam.height), cam.near_clip, cam.far_clip}) +
         numbers({cam.position.x, cam.position.y, cam.position.z, cam.target.x, cam.target.y, cam.target.z}) +
         numbers({phi, theta, r, r * 0.1, r * 10.0}) +
         numbers({x.x, y.x, z.x, x.y, y.y, z.y, x.z, y.z, z.z}) +
         numbers({double(cam.width), double(cam.height), cam.screen_dist}) +
         numbers({cam.focal_distance, cam.lens_radius});
}

}  // namespace pt::viewer
