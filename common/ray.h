// A ray with its valid parameter interval [min_t, max_t]. Intersection
// routines shrink max_t to the nearest hit found so far, so later tests only
// accept nearer hits (the course's convention).
#pragma once
#include <limits>

#include "common/vec3.h"

namespace pt {

// Offset of shadow and bounce rays from the surface they leave (their
// min_t), and how far short of a sampled light a shadow ray stops
// (max_t = distance - eps). A ray's min_t defaults to it, so that a ray
// started on a surface does not find that surface again. The course's rays
// are double precision and offset by its EPS_D = 1e-11; in float rays that
// is no offset at all, and every shadow ray from a surface would hit the
// surface it starts on (images about half as bright): use kRayEpsilon.
constexpr float kRayEpsilon = 1e-4f;

struct Ray {
  Vec3 o;                 // origin
  Vec3 d;                 // direction (unit length for camera and bounce rays)
  float min_t = kRayEpsilon;
  float max_t = std::numeric_limits<float>::infinity();
  int depth = 0;          // remaining bounces (parts 4 and 5)

  Ray() = default;
  Ray(const Vec3& o_, const Vec3& d_, float min_t_ = kRayEpsilon,
      float max_t_ = std::numeric_limits<float>::infinity(), int depth_ = 0)
      : o(o_), d(d_), min_t(min_t_), max_t(max_t_), depth(depth_) {}

  Vec3 at(float t) const { return o + d * t; }
};

// What a closest-hit query reports.
struct Hit {
  float t = std::numeric_limits<float>::infinity();
  Vec3 n;                 // unit shading normal (interpolated for triangles)
  int material = -1;      // index into Scene::materials
  int primitive = -1;     // triangle index, or num_triangles + sphere index
};

}  // namespace pt
