#include "common/camera.h"

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "common/math_constants.h"

namespace pt {

namespace {
double rad(double deg) { return deg * kPiDouble / 180.0; }
double deg(double rad) { return rad * 180.0 / kPiDouble; }
}  // namespace

double fov_across(double fov_deg, double ratio) {
  return deg(2 * std::atan(std::tan(rad(fov_deg) / 2) * ratio));
}

void Camera::look_at(const Vec3d& pos, const Vec3d& at, const Vec3d& up) {
  position = pos;
  target = at;
  Vec3d w = pos - at;
  if (norm(w) == 0.0) w = Vec3d(0, 0, 1);
  w = normalize(w);
  Vec3d u = cross(up, w);
  if (norm(u) < 1e-9) u = cross(Vec3d(0, 0, 1), w);  // looking straight up or down
  u = normalize(u);
  axis_x = u;
  axis_y = cross(w, u);
  axis_z = w;
}

void Camera::fit_course_frame(double xfov_deg, double yfov_deg) {
  const double ar = 800.0 / 600.0;
  double th = std::tan(rad(xfov_deg) / 2), tv = std::tan(rad(yfov_deg) / 2);
  if (th / tv > ar)
    tv = th / ar;  // vertical too narrow for 4:3: widen it
  else
    th = tv * ar;  // horizontal too narrow: widen it
  screen_dist = 600.0 / (2.0 * tv);
  width = 800;
  height = 600;
  hfov_deg = deg(2 * std::atan(th));
  vfov_deg = deg(2 * std::atan(tv));
}

void Camera::set_resolution(int w, int h) {
  width = w;
  height = h;
  hfov_deg = deg(2 * std::atan(w / (2.0 * screen_dist)));
  vfov_deg = deg(2 * std::atan(h / (2.0 * screen_dist)));
}

void Camera::place_course(const Vec3d& dir, const BBox& bounds) {
  const Vec3d c(bounds.centroid());
  const double dist = 1.5 * norm(Vec3d(bounds.extent()));
  look_at(c + normalize(dir) * dist, c, Vec3d(0, 1, 0));
}

void Camera::load_settings(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open camera settings file");
  // Expected numbers per line.
  const int counts[6] = {5, 6, 5, 9, 3, 2};
  std::vector<std::vector<double>> rows;
  std::vector<int> rows_lines;  // the file line each row came from
  std::string line;
  int lineno = 0;
  while (rows.size() < 6 && std::getline(in, line)) {
    ++lineno;
    std::istringstream ls(line);
    std::vector<double> v;
    std::string tok;
    while (ls >> tok) {
      try {
        size_t used = 0;
        double x = std::stod(tok, &used);
        if (used != tok.size() || !std::isfinite(x)) throw std::invalid_argument(tok);
        v.push_back(x);
      } catch (const std::exception&) {
        throw std::runtime_error(path + ": line " + std::to_string(lineno) + ": '" + tok +
                                 "' is not a finite number");
      }
    }
    if (v.empty()) continue;  // blank line
    const int want = counts[rows.size()];
    if (int(v.size()) != want)
      throw std::runtime_error(path + ": line " + std::to_string(lineno) + ": expected " +
                               std::to_string(want) + " numbers, found " +
                               std::to_string(v.size()));
    rows.push_back(v);
    rows_lines.push_back(lineno);
  }
  if (rows.size() != 6)
    throw std::runtime_error(path + ": expected 6 lines of camera settings, found " +
                             std::to_string(rows.size()));
  const auto& r0 = rows[0];
  const std::string line1 = path + ": line " + std::to_string(rows_lines[0]);
  if (r0[0] <= 0 || r0[0] >= 180 || r0[1] <= 0 || r0[1] >= 180)
    throw std::runtime_error(line1 + ": field of view must be in (0, 180) degrees");
  if (r0[3] < 0 || r0[4] <= r0[3]) throw std::runtime_error(line1 + ": need 0 <= nClip < fClip");
  const auto& m = rows[3];  // row-major camera-to-world; columns are the axes
  const Vec3d ax(m[0], m[3], m[6]), ay(m[1], m[4], m[7]), az(m[2], m[5], m[8]);
  // The course writes a rotation here. Anything else (a zero or scaled axis,
  // two parallel axes, a mirror) would skew or flatten the image, so it is
  // refused; the tolerance admits a rotation written to six digits.
  const double tol = 1e-3;
  const char* const names[3] = {"first", "second", "third"};
  const Vec3d axes[3] = {ax, ay, az};
  for (int i = 0; i < 3; ++i)
    if (!(std::fabs(norm(axes[i]) - 1.0) <= tol))
      throw std::runtime_error(path + ": line " + std::to_string(rows_lines[3]) +
                               ": the camera-to-world matrix must be a rotation; its " + names[i] +
                               " column has length " + std::to_string(norm(axes[i])) + ", not 1");
  if (!(std::fabs(dot(ax, ay)) <= tol && std::fabs(dot(ax, az)) <= tol && std::fabs(dot(ay, az)) <= tol))
    throw std::runtime_error(path + ": line " + std::to_string(rows_lines[3]) +
                             ": the camera-to-world matrix must be a rotation; its columns are not at right angles");
  if (!(dot(cross(ax, ay), az) > 0))
    throw std::runtime_error(path + ": line " + std::to_string(rows_lines[3]) +
                             ": the camera-to-world matrix must be a rotation; it is a mirror image (determinant -1)");
  if (!(rows[5][0] > 0))
    throw std::runtime_error(path + ": line " + std::to_string(rows_lines[5]) +
                             ": the focal distance must be positive, found " + std::to_string(rows[5][0]));
  if (rows[5][1] < 0)
    throw std::runtime_error(path + ": line " + std::to_string(rows_lines[5]) + ": lens radius must be >= 0");
  // Everything is valid: only now does the camera change.
  hfov_deg = r0[0];
  vfov_deg = r0[1];
  near_clip = r0[3];
  far_clip = r0[4];
  position = Vec3d(rows[1][0], rows[1][1], rows[1][2]);
  target = Vec3d(rows[1][3], rows[1][4], rows[1][5]);
  axis_x = ax;
  axis_y = ay;
  axis_z = az;
  if (rows[4][2] > 0) screen_dist = rows[4][2];
  focal_distance = rows[5][0];
  lens_radius = rows[5][1];
}

}  // namespace pt
