// Scenes whose light has a closed form (header-only): irradiance, solid
// angle and sampling density of rectangular area lights, computed in double
// precision independently of common/lights.h, and small builders for scenes
// made in code (materials, quads, area lights, cameras).
#pragma once
#include <algorithm>
#include <cmath>
#include <vector>

#include "common/scene.h"

namespace pt::test {

// ---------------------------------------------------------------------------
// Closed forms for rectangular area lights (computed in double precision,
// independently of common/lights.h)

inline Vec3d to_d(const Vec3& v) { return Vec3d(v.x, v.y, v.z); }

// Where the ray p + t w (w unit) meets the plane of the light's
// parallelogram: the distance t > 0 and the coordinates (a, b) of the point
// c + a dim_x + b dim_y; the point is on the light when |a|, |b| <= 1/2.
// Returns false when the ray is parallel to the plane or points away.
inline bool area_light_plane_hit(const Light& l, const Vec3d& p, const Vec3d& w, double* a, double* b, double* t) {
  const Vec3d c = to_d(l.position), dx = to_d(l.dim_x), dy = to_d(l.dim_y);
  const Vec3d n = normalize(cross(dx, dy));
  const double denom = dot(w, n);
  if (std::fabs(denom) < 1e-300) return false;
  *t = dot(c - p, n) / denom;
  if (!(*t > 0)) return false;
  const Vec3d q = p + w * *t - c;
  // q = a dx + b dy: solve the 2 x 2 Gram system.
  const double g11 = dot(dx, dx), g12 = dot(dx, dy), g22 = dot(dy, dy);
  const double r1 = dot(q, dx), r2 = dot(q, dy), det = g11 * g22 - g12 * g12;
  *a = (r1 * g22 - r2 * g12) / det;
  *b = (g11 * r2 - g12 * r1) / det;
  return true;
}

// The density per steradian, at direction w from p, of the directions to a
// uniformly chosen point of the light's parallelogram: t^2 / (A cos) where
// the ray p + t w meets the light, on its emitting side only; 0 where it
// misses.
inline double area_light_density(const Light& l, const Vec3& p, const Vec3& w_) {
  const Vec3d w = normalize(to_d(w_));
  double a, b, t;
  if (!area_light_plane_hit(l, to_d(p), w, &a, &b, &t)) return 0.0;
  if (std::fabs(a) > 0.5 || std::fabs(b) > 0.5) return 0.0;
  const double cos_l = -dot(w, normalize(to_d(l.direction)));
  if (!(cos_l > 0)) return 0.0;
  return t * t / (norm(cross(to_d(l.dim_x), to_d(l.dim_y))) * cos_l);
}

// The light's corners in order around the parallelogram.
inline std::vector<Vec3d> area_light_corners(const Light& l) {
  const Vec3d c = to_d(l.position), hx = to_d(l.dim_x) * 0.5, hy = to_d(l.dim_y) * 0.5;
  return {c - hx - hy, c + hx - hy, c + hx + hy, c - hx + hy};
}

// Irradiance at p (normal n) from a polygon of uniform radiance L, by
// Lambert's formula E = (L / 2) |sum_i theta_i n . (a_i x b_i) / |a_i x b_i||
// with a_i, b_i the unit vectors to consecutive vertices and theta_i the
// angle between them, after clipping the polygon to the half-space above
// the tangent plane of p (the part below sends no light to p).
inline double polygon_irradiance(std::vector<Vec3d> poly, const Vec3d& p, const Vec3d& n, double L) {
  // Sutherland-Hodgman against n . (x - p) >= 0.
  std::vector<Vec3d> clipped;
  for (size_t i = 0; i < poly.size(); ++i) {
    const Vec3d& a = poly[i];
    const Vec3d& b = poly[(i + 1) % poly.size()];
    const double da = dot(n, a - p), db = dot(n, b - p);
    if (da >= 0) clipped.push_back(a);
    if ((da >= 0) != (db >= 0)) clipped.push_back(a + (b - a) * (da / (da - db)));
  }
  if (clipped.size() < 3) return 0.0;
  double sum = 0;
  for (size_t i = 0; i < clipped.size(); ++i) {
    const Vec3d a = normalize(clipped[i] - p), b = normalize(clipped[(i + 1) % clipped.size()] - p);
    const Vec3d axb = cross(a, b);
    const double s = norm(axb);
    if (s < 1e-300) continue;
    const double theta = std::atan2(s, dot(a, b));
    sum += theta * dot(n, axb) / s;
  }
  return 0.5 * L * std::fabs(sum);
}

// Irradiance at p (normal n) from a one-sided rectangular area light of
// radiance L: zero behind the light.
inline double area_light_irradiance(const Light& l, const Vec3& p, const Vec3& n, double L) {
  if (dot(to_d(p) - to_d(l.position), to_d(l.direction)) <= 0) return 0.0;
  return polygon_irradiance(area_light_corners(l), to_d(p), normalize(to_d(n)), L);
}

// Solid angle of a planar convex polygon seen from p (sum of the triangles
// of a fan, Van Oosterom and Strackee's formula).
inline double polygon_solid_angle(const std::vector<Vec3d>& poly, const Vec3d& p) {
  double total = 0;
  for (size_t i = 1; i + 1 < poly.size(); ++i) {
    const Vec3d a = poly[0] - p, b = poly[i] - p, c = poly[i + 1] - p;
    const double la = norm(a), lb = norm(b), lc = norm(c);
    const double num = dot(a, cross(b, c));
    const double den = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la;
    total += 2.0 * std::fabs(std::atan2(num, den));
  }
  return total;
}

// ---------------------------------------------------------------------------
// Scenes built in code

inline int add_material(Scene& s, const Material& m) {
  s.materials.push_back(m);
  return int(s.materials.size()) - 1;
}
inline Material diffuse_material(const Color& albedo) {
  Material m;
  m.name = "diffuse";
  m.type = MaterialType::Diffuse;
  m.albedo = albedo;
  return m;
}
inline Material emissive_material(const Color& radiance) {
  Material m;
  m.name = "emission";
  m.type = MaterialType::Emission;
  m.albedo = Color(0.0f);
  m.emission = radiance;
  return m;
}

// The parallelogram corner, corner + e1, corner + e1 + e2, corner + e2 as two
// triangles with the flat normal `facing` (unit).
inline void add_quad(Scene& s, const Vec3& corner, const Vec3& e1, const Vec3& e2, const Vec3& facing, int material) {
  Triangle a, b;
  a.p1 = corner;
  a.p2 = corner + e1;
  a.p3 = corner + e1 + e2;
  b.p1 = corner;
  b.p2 = corner + e1 + e2;
  b.p3 = corner + e2;
  a.n1 = a.n2 = a.n3 = b.n1 = b.n2 = b.n3 = facing;
  a.material = b.material = material;
  s.triangles.push_back(a);
  s.triangles.push_back(b);
}

// A one-sided rectangular area light centred at `center`, spanning
// center +- dim_x / 2 +- dim_y / 2, emitting along `direction`.
inline Light area_light(const Vec3& center, const Vec3& dim_x, const Vec3& dim_y, const Vec3& direction,
                        const Color& radiance) {
  Light l;
  l.type = LightType::Area;
  l.position = center;
  l.dim_x = dim_x;
  l.dim_y = dim_y;
  l.direction = direction;
  l.radiance = radiance;
  return l;
}

// Adds an area light together with an emissive quad covering exactly its
// rectangle (so that hemisphere sampling sees what light sampling samples).
inline void add_area_light_with_quad(Scene& s, const Light& l) {
  const int m = add_material(s, emissive_material(l.radiance));
  add_quad(s, l.position - l.dim_x * 0.5f - l.dim_y * 0.5f, l.dim_x, l.dim_y, l.direction, m);
  s.lights.push_back(l);
}

// Points the camera from `eye` at `at` (world up +Y) with vertical field of
// view vfov_deg and an image of w x h pixels.
inline void aim_camera(Camera& cam, const Vec3d& eye, const Vec3d& at, double vfov_deg, int w, int h) {
  cam.look_at(eye, at, Vec3d(0, 1, 0));
  cam.screen_dist = h / (2.0 * std::tan(vfov_deg * M_PI / 360.0));
  cam.set_resolution(w, h);
}

// Shows a loaded scene's whole 800 x 600 course view in a w x h image (the
// renderer's -r keeps the focal length in pixels, i.e. crops the view).
inline void fit_course_view(Camera& cam, int w, int h) {
  cam.screen_dist *= double(h) / 600.0;
  cam.set_resolution(w, h);
}

}  // namespace pt::test
