// 3-vectors for points, directions, normals and RGB colours.
// Geometry is stored and traced in float (speed); the loader and the camera
// set-up compute in double (Vec3d) and convert once.
#pragma once
#include <algorithm>
#include <cmath>

namespace pt {

template <typename T>
struct Vec3T {
  T x = 0, y = 0, z = 0;

  constexpr Vec3T() = default;
  constexpr Vec3T(T x_, T y_, T z_) : x(x_), y(y_), z(z_) {}
  constexpr explicit Vec3T(T v) : x(v), y(v), z(v) {}
  template <typename U>
  constexpr explicit Vec3T(const Vec3T<U>& o) : x(T(o.x)), y(T(o.y)), z(T(o.z)) {}

  constexpr T operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  T& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }

  constexpr Vec3T operator+(const Vec3T& o) const { return {x + o.x, y + o.y, z + o.z}; }
  constexpr Vec3T operator-(const Vec3T& o) const { return {x - o.x, y - o.y, z - o.z}; }
  constexpr Vec3T operator*(const Vec3T& o) const { return {x * o.x, y * o.y, z * o.z}; }
  constexpr Vec3T operator/(const Vec3T& o) const { return {x / o.x, y / o.y, z / o.z}; }
  constexpr Vec3T operator*(T s) const { return {x * s, y * s, z * s}; }
  constexpr Vec3T operator/(T s) const { return {x / s, y / s, z / s}; }
  constexpr Vec3T operator-() const { return {-x, -y, -z}; }
  Vec3T& operator+=(const Vec3T& o) { x += o.x; y += o.y; z += o.z; return *this; }
  Vec3T& operator-=(const Vec3T& o) { x -= o.x; y -= o.y; z -= o.z; return *this; }
  Vec3T& operator*=(const Vec3T& o) { x *= o.x; y *= o.y; z *= o.z; return *this; }
  Vec3T& operator*=(T s) { x *= s; y *= s; z *= s; return *this; }
  Vec3T& operator/=(T s) { x /= s; y /= s; z /= s; return *this; }
  constexpr bool operator==(const Vec3T& o) const { return x == o.x && y == o.y && z == o.z; }
  constexpr bool operator!=(const Vec3T& o) const { return !(*this == o); }
};

template <typename T>
constexpr Vec3T<T> operator*(T s, const Vec3T<T>& v) { return v * s; }

template <typename T>
constexpr T dot(const Vec3T<T>& a, const Vec3T<T>& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

template <typename T>
constexpr Vec3T<T> cross(const Vec3T<T>& a, const Vec3T<T>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

template <typename T>
inline T norm2(const Vec3T<T>& v) { return dot(v, v); }

template <typename T>
inline T norm(const Vec3T<T>& v) { return std::sqrt(dot(v, v)); }

template <typename T>
inline Vec3T<T> normalize(const Vec3T<T>& v) { return v / norm(v); }

template <typename T>
inline Vec3T<T> vmin(const Vec3T<T>& a, const Vec3T<T>& b) {
  return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
}

template <typename T>
inline Vec3T<T> vmax(const Vec3T<T>& a, const Vec3T<T>& b) {
  return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
}

template <typename T>
inline bool is_finite(const Vec3T<T>& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

using Vec3 = Vec3T<float>;
using Vec3d = Vec3T<double>;

// Linear RGB radiance. A separate name (same type) so that signatures say
// whether a value is a colour or a direction.
using Color = Vec3;

// Illuminance (luminance weights used by the course for adaptive sampling).
inline float illum(const Color& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

// Whether a colour is exactly zero in every channel (no light at all).
inline bool is_black(const Color& c) { return c.x == 0 && c.y == 0 && c.z == 0; }

}  // namespace pt
