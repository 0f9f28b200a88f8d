// 4x4 affine transforms in double precision, column-vector convention
// (p' = M * p), stored row-major like COLLADA's <matrix>.
#pragma once
#include "common/math_constants.h"
#include "common/vec3.h"

namespace pt {

struct Mat4 {
  double m[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};

  static Mat4 identity() { return Mat4{}; }
  static Mat4 from_row_major(const double* v) {
    Mat4 r;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) r.m[i][j] = v[4 * i + j];
    return r;
  }
  static Mat4 translate(const Vec3d& t) {
    Mat4 r;
    r.m[0][3] = t.x; r.m[1][3] = t.y; r.m[2][3] = t.z;
    return r;
  }
  static Mat4 scale(const Vec3d& s) {
    Mat4 r;
    r.m[0][0] = s.x; r.m[1][1] = s.y; r.m[2][2] = s.z;
    return r;
  }
  // Right-handed rotation by `degrees` about `axis` (need not be unit length).
  static Mat4 rotate(const Vec3d& axis, double degrees) {
    const Vec3d a = normalize(axis);
    const double th = degrees * kPiDouble / 180.0;
    const double c = std::cos(th), s = std::sin(th), C = 1 - c;
    Mat4 r;
    r.m[0][0] = a.x * a.x * C + c;       r.m[0][1] = a.x * a.y * C - a.z * s; r.m[0][2] = a.x * a.z * C + a.y * s;
    r.m[1][0] = a.y * a.x * C + a.z * s; r.m[1][1] = a.y * a.y * C + c;       r.m[1][2] = a.y * a.z * C - a.x * s;
    r.m[2][0] = a.z * a.x * C - a.y * s; r.m[2][1] = a.z * a.y * C + a.x * s; r.m[2][2] = a.z * a.z * C + c;
    return r;
  }

  Mat4 operator*(const Mat4& o) const {
    Mat4 r;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) {
        double s = 0;
        for (int k = 0; k < 4; ++k) s += m[i][k] * o.m[k][j];
        r.m[i][j] = s;
      }
    return r;
  }
  // Full homogeneous product of (x, y, z, w); returns the xyz part.
  Vec3d apply(const Vec3d& v, double w) const {
    return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z + m[0][3] * w,
            m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z + m[1][3] * w,
            m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z + m[2][3] * w};
  }
  Vec3d point(const Vec3d& p) const { return apply(p, 1.0); }
  Vec3d vector(const Vec3d& v) const { return apply(v, 0.0); }
};

}  // namespace pt
