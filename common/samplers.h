// Direction samplers on the unit hemisphere around +Z (the local shading
// frame's normal), from two uniform numbers in [0, 1).
#pragma once
#include <cmath>

#include "common/math_constants.h"
#include "common/vec3.h"

namespace pt {

// Uniform over the hemisphere z >= 0; pdf 1 / (2 pi) per steradian.
inline Vec3 sample_uniform_hemisphere(float u1, float u2) {
  const float z = u1;
  const float r = std::sqrt(std::fmax(0.0f, 1.0f - z * z));
  const float phi = 2.0f * kPi * u2;
  return {r * std::cos(phi), r * std::sin(phi), z};
}
inline float uniform_hemisphere_pdf() { return kInv2Pi; }

// Cosine-weighted over the hemisphere z >= 0; pdf cos(theta) / pi.
inline Vec3 sample_cosine_hemisphere(float u1, float u2) {
  const float r = std::sqrt(u1);
  const float phi = 2.0f * kPi * u2;
  return {r * std::cos(phi), r * std::sin(phi), std::sqrt(std::fmax(0.0f, 1.0f - u1))};
}
inline float cosine_hemisphere_pdf(const Vec3& w) { return w.z > 0 ? w.z * kInvPi : 0.0f; }

}  // namespace pt
