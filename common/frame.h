// The local shading frame: an orthonormal basis whose z axis is the
// surface normal. BSDFs and hemisphere samplers work in it.
#pragma once
#include <cmath>

#include "common/vec3.h"

namespace pt {

struct Frame {
  Vec3 x, y, z;

  // A frame with z = n (unit). Branch-free construction (Duff et al. 2017).
  static Frame from_normal(const Vec3& n) {
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z);
    const float b = n.x * n.y * a;
    Frame f;
    f.x = Vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
    f.y = Vec3(b, sign + n.y * n.y * a, -n.y);
    f.z = n;
    return f;
  }
  Vec3 to_local(const Vec3& w) const { return {dot(w, x), dot(w, y), dot(w, z)}; }
  Vec3 to_world(const Vec3& w) const { return x * w.x + y * w.y + z * w.z; }
};

}  // namespace pt
