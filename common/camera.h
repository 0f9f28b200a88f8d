// The pinhole (optionally thin-lens) camera and the course's rules for
// placing it and fitting its field of view. Ray generation itself is
// student code: the pinhole's in Part 1 (stages/part1_raytracing/
// camera_rays.cpp), the thin lens's in Part 9
// (stages/part9_depth_of_field/thin_lens.cpp).
#pragma once
#include <string>

#include "common/bbox.h"
#include "common/vec3.h"

namespace pt {

struct Ray;  // common/ray.h

// The full field of view (degrees) across one side of a frame, from the
// full field of view across the other side and the ratio of the sides
// (this side / that side): 2 atan(tan(fov / 2) * ratio). For a frame of
// aspect ratio w / h, yfov = fov_across(xfov, h / w), xfov =
// fov_across(yfov, w / h).
double fov_across(double fov_deg, double ratio);

struct Camera {
  Vec3d position{0, 0, 0};
  Vec3d target{0, 0, -1};
  // Camera-to-world rotation as three world-space axes: the camera looks
  // along -axis_z, axis_x points right and axis_y up on the image.
  Vec3d axis_x{1, 0, 0}, axis_y{0, 1, 0}, axis_z{0, 0, 1};

  double hfov_deg = 50.0;     // full horizontal field of view
  double vfov_deg = 37.5;     // full vertical field of view
  double near_clip = 0.001;   // camera rays start here (min_t)
  double far_clip = 1000.0;   // and end here (max_t)

  // Focal length in pixels, fixed by the course's 800x600 frame; keeps the
  // scale of the image when -r changes the resolution.
  double screen_dist = 600.0 / (2.0 * 0.3394);

  // Thin lens (-b, -d). A lens radius of 0 is a pinhole.
  double lens_radius = 0.0;
  double focal_distance = 4.7;
  // The thin lens's ray through normalised image point (x, y) with lens
  // sample (u1, u2) in [0, 1)^2: part 9's generate_ray_for_thin_lens, set
  // by the render for --part 9 and later. Until then (null) the camera is
  // a pinhole whatever lens_radius says, as before the course's part 4 of
  // 3-2.
  Ray (*thin_lens)(const Camera& cam, double x, double y, double u1, double u2) = nullptr;

  int width = 800, height = 600;  // image size in pixels

  // Camera-to-world: local (x, y, z) direction -> world direction.
  Vec3d to_world(const Vec3d& v) const { return axis_x * v.x + axis_y * v.y + axis_z * v.z; }

  // Orient the camera at `pos` toward `look_at` with `up` as the world up
  // (falls back to +Z when the view direction is parallel to `up`).
  void look_at(const Vec3d& pos, const Vec3d& look_at, const Vec3d& up);

  // The course's field-of-view fit: given the file's horizontal FOV and
  // vertical FOV, widen whichever is too narrow for a 4:3 (800x600) frame and
  // fix the focal length in pixels from it.
  void fit_course_frame(double xfov_deg, double yfov_deg);

  // Change the output size keeping the focal length in pixels, so that a
  // smaller image is a centre crop of the 800x600 view.
  void set_resolution(int w, int h);

  // The course's placement: look from target + 1.5 |extent| * dir at the
  // centre of `bounds`, world up +Y.
  void place_course(const Vec3d& dir, const BBox& bounds);

  // Read a camera settings file (the course's -c format, six lines). Throws
  // std::runtime_error naming the file and line on malformed input: a token
  // that is not a finite number, a wrong count, a field of view outside
  // (0, 180), not 0 <= nClip < fClip, a camera-to-world matrix that is not
  // a rotation (within 1e-3), a focal distance <= 0 or a negative lens
  // radius. The camera is left unchanged when the file is refused.
  void load_settings(const std::string& path);
};

}  // namespace pt

