// The scene's camera (see camera_reader.h).
#include "common/collada/camera_reader.h"

#include <cmath>
#include <string>

#include "common/camera.h"
#include "common/collada/xml_values.h"

namespace pt::collada {

namespace {

// Defaults used when the scene has no camera (see docs/scene-format.md).
constexpr double kFallbackXfov = 50.0;
constexpr double kFallbackAspect = 4.0 / 3.0;

}  // namespace

void CameraReader::add(const XMLElement* inst, const Mat4& world, Camera& camera) {
  const XMLElement* cam = doc_.resolve(inst, "url", "camera");
  if (have_camera_) return;  // the first camera met is the scene's camera
  have_camera_ = true;

  const XMLElement* optics = cam->FirstChildElement("optics");
  const XMLElement* tc = optics ? optics->FirstChildElement("technique_common") : nullptr;
  const XMLElement* persp = tc ? tc->FirstChildElement("perspective") : nullptr;
  FieldOfView fov;
  if (!persp)
    msg_.warn(cam, "not a perspective camera; using a " + fmt(kFallbackXfov) + " degree horizontal field of view");
  else
    read_perspective(persp, fov, camera);
  complete(persp ? persp : cam, fov);
  read_direction(inst, world);
}

void CameraReader::read_perspective(const XMLElement* persp, FieldOfView& fov, Camera& camera) {
  msg_.check_children(persp, {"xfov", "yfov", "aspect_ratio", "znear", "zfar"});
  auto read = [&](const char* name, double& out) {
    const XMLElement* e = persp->FirstChildElement(name);
    if (!e) return false;
    out = scalar(msg_, e, name);
    return true;
  };
  if ((fov.has_x = read("xfov", fov.xfov)) && !(fov.xfov > 0 && fov.xfov < 180))
    msg_.fail(persp->FirstChildElement("xfov"),
              "the field of view must be in (0, 180) degrees, found " + fmt(fov.xfov));
  if ((fov.has_y = read("yfov", fov.yfov)) && !(fov.yfov > 0 && fov.yfov < 180))
    msg_.fail(persp->FirstChildElement("yfov"),
              "the field of view must be in (0, 180) degrees, found " + fmt(fov.yfov));
  if ((fov.has_aspect = read("aspect_ratio", fov.aspect)) && !(fov.aspect > 0))
    msg_.fail(persp->FirstChildElement("aspect_ratio"),
              "the aspect ratio must be positive, found " + fmt(fov.aspect));
  double znear = 0.001, zfar = 1000.0;
  read("znear", znear);
  read("zfar", zfar);
  if (!(znear >= 0) || !(zfar > znear))
    msg_.fail(persp, "needs 0 <= znear < zfar, found znear " + fmt(znear) + ", zfar " + fmt(zfar));
  camera.near_clip = znear;
  camera.far_clip = zfar;
  if (!fov.has_x && !fov.has_y) msg_.fail(persp, "needs <xfov> or <yfov>");
}

// The missing field of view from the other and the aspect ratio (both
// defaulted when absent), checked to leave a frame an image can show.
void CameraReader::complete(const XMLElement* e, FieldOfView fov) {
  if (!fov.has_x && !fov.has_y) {
    fov.xfov = kFallbackXfov;
    fov.has_x = true;
  }
  if (!fov.has_aspect) fov.aspect = kFallbackAspect;
  if (fov.has_x && !fov.has_y) fov.yfov = fov_across(fov.xfov, 1.0 / fov.aspect);
  if (fov.has_y && !fov.has_x) fov.xfov = fov_across(fov.yfov, fov.aspect);
  // An extreme aspect ratio (or field of view) leaves a frame of no width
  // or of 180 degrees, which no image can show.
  const double xfov = fov.xfov, yfov = fov.yfov;
  Camera fitted;
  fitted.fit_course_frame(xfov, yfov);
  if (!(xfov > 0 && xfov < 180 && yfov > 0 && yfov < 180) || !std::isfinite(fitted.screen_dist) ||
      !(fitted.screen_dist > 0) || !(fitted.hfov_deg > 0 && fitted.hfov_deg < 180) ||
      !(fitted.vfov_deg > 0 && fitted.vfov_deg < 180))
    msg_.fail(e, "the field of view " + fmt(xfov) + " x " + fmt(yfov) +
                     " degrees (from xfov, yfov and aspect_ratio) is too narrow or too wide to render");
  xfov_ = xfov;
  yfov_ = yfov;
}

// The course's rule: the direction from the origin to the point one unit
// in front of the camera (see docs/scene-format.md).
void CameraReader::read_direction(const XMLElement* inst, const Mat4& world) {
  const Vec3d ahead = world.point({0, 0, -1});
  if (!is_finite(ahead) || norm2(ahead) == 0) {
    msg_.warn(inst, "the point in front of the camera is the origin; viewing along -Z instead");
    camera_dir_ = Vec3d(0, 0, 1);
  } else {
    camera_dir_ = normalize(ahead);
  }
}

void CameraReader::finish(const XMLElement* vscene, Scene& scene) {
  if (!have_camera_) {
    msg_.warn(vscene, "no camera in the scene; looking along -Z with a " + fmt(kFallbackXfov) +
                          " degree horizontal field of view");
    xfov_ = kFallbackXfov;
    yfov_ = fov_across(kFallbackXfov, 1.0 / kFallbackAspect);
    camera_dir_ = Vec3d(0, 0, 1);
  }
  // The renderer works in float: a scene whose bounds overflow it (a huge
  // sphere radius or scale) would put the camera at infinity.
  const BBox bounds = scene.bounds();
  const Vec3 lo = bounds.lo, hi = bounds.hi;
  if (!is_finite(lo) || !is_finite(hi) || !is_finite(bounds.extent()) || !is_finite(bounds.centroid()))
    msg_.fail(vscene, "the scene is too large for single-precision numbers: its bounds reach " + fmt(Vec3d(lo)) +
                          " to " + fmt(Vec3d(hi)));
  scene.camera.fit_course_frame(xfov_, yfov_);
  scene.camera.place_course(camera_dir_, bounds);
  if (!is_finite(Vec3(scene.camera.position)))
    msg_.fail(vscene, "the scene is too large for single-precision numbers: the camera would stand at " +
                          fmt(scene.camera.position));
}

}  // namespace pt::collada
