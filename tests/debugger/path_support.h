// What the path inspector's tests share: exact comparisons, a colour as
// text, the options of a small render, a project scene in the course's
// view, and geometry that throws (a student's failing code).
#pragma once
#include <cstring>
#include <sstream>
#include <stdexcept>
#include <string>

#include "common/collada.h"
#include "common/intersector.h"
#include "pathtracer/options.h"
#include "tests/statistics/analytic_scenes.h"
#include "tests/support.h"

namespace pt::test::path {

inline bool same_bits(const Color& a, const Color& b) {
  const float x[3] = {a.x, a.y, a.z}, y[3] = {b.x, b.y, b.z};
  return std::memcmp(x, y, sizeof x) == 0;
}

inline bool same_bits(const Vec3& a, const Vec3& b, float s, float t) {
  return same_bits(a, b) && std::memcmp(&s, &t, sizeof s) == 0;
}

inline std::string show(const Color& c) {
  std::ostringstream o;
  o.precision(9);
  o << "(" << c.x << ", " << c.y << ", " << c.z << ")";
  return o.str();
}

inline RenderOptions options(int part, int w, int h, int spp, int max_depth, uint64_t seed) {
  RenderOptions o;
  o.part = part;
  o.width = w;
  o.height = h;
  o.samples_per_pixel = spp;
  o.max_depth = max_depth;
  o.seed = seed;
  o.threads = 1;
  o.progress = false;
  return o;
}

inline Scene small_scene(const std::string& name, int w, int h) {
  Scene s = load_collada(project_scene(name));
  fit_course_view(s.camera, w, h);
  return s;
}

// Geometry standing in for a student's that throws.
class ThrowingGeometry final : public Intersector {
 public:
  bool intersect(Ray&, Hit*) const override { throw std::runtime_error("node index out of range"); }
  bool occluded(const Ray&) const override { return false; }
};

}  // namespace pt::test::path
