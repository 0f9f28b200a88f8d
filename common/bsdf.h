// Surface scattering in the local shading frame (z = normal). Only the
// diffuse BSDF is used by the five parts; mirror, glass, refraction and
// microfacet materials are shaded as diffuse with their albedo (see
// docs/differences.md).
#pragma once
#include "common/samplers.h"
#include "common/scene.h"

namespace pt {

// BSDF value for light arriving along wi and leaving along wo (both local,
// pointing away from the surface).
// Diffuse: albedo / pi. As in the course it does not look at the sides of
// wo and wi; the estimators skip light directions below the surface.
inline Color bsdf_f(const Material& m, const Vec3& wo, const Vec3& wi) {
  (void)wo;
  (void)wi;
  if (m.type == MaterialType::Emission) return Color(0.0f);
  return m.albedo * kInvPi;
}

// Samples wi for outgoing wo: cosine-weighted about the normal. Returns f
// and sets *wi and *pdf.
inline Color bsdf_sample_f(const Material& m, const Vec3& wo, float u1, float u2, Vec3* wi, float* pdf) {
  *wi = sample_cosine_hemisphere(u1, u2);
  *pdf = cosine_hemisphere_pdf(*wi);
  return bsdf_f(m, wo, *wi);
}

inline float bsdf_pdf(const Material& m, const Vec3& wo, const Vec3& wi) {
  (void)m;
  (void)wo;
  return cosine_hemisphere_pdf(wi);
}

inline Color emission(const Material& m) { return m.emission; }

}  // namespace pt
