// Surface scattering in the local shading frame (z = normal): what the
// lighting code of parts 3 and 4 calls (bsdf_f, bsdf_sample_f, bsdf_pdf,
// bsdf_is_delta), the diffuse BSDF, and the interface through which the
// BSDFs of later parts (part 6: mirror, glass, refraction; part 7:
// microfacet) are reached.
//
// A BSDFModel is the table of one kind of surface's functions. Each
// material points to its model (Material::model); the render sets the
// pointers for the parts it renders (pathtracer/radiance.cpp), so that
// `--part 5` shades a mirror as the course's starter code does (black) and
// `--part 6` with part 6's mirror. A material without a model uses the
// given default of its type: diffuse for Diffuse, nothing reflected for
// Emission and for the types a later part writes.
#pragma once
#include "common/samplers.h"
#include "common/scene.h"

namespace pt {

struct BSDFModel {
  const char* name;
  // BSDF value for light arriving along wi and leaving along wo (both
  // local, unit, pointing away from the surface). 0 for a delta BSDF.
  Color (*f)(const Material& m, const Vec3& wo, const Vec3& wi);
  // Draws wi for outgoing wo from two uniform numbers in [0, 1); sets *wi
  // and *pdf (per unit solid angle; for a delta BSDF the probability of
  // the choice made, e.g. glass's reflection) and returns f, for a delta
  // BSDF the delta's weight divided by |cos theta_i|, so that f |cos| / pdf
  // is the sample's weight either way. *pdf = 0: no direction (the path
  // ends).
  Color (*sample_f)(const Material& m, const Vec3& wo, float u1, float u2, Vec3* wi, float* pdf);
  // The density sample_f draws wi with (0 for a delta BSDF).
  float (*pdf)(const Material& m, const Vec3& wo, const Vec3& wi);
  // Scatters into single directions (mirror, glass): light sampling cannot
  // find them, so the path's next hit brings its emission instead (part 4).
  bool delta;
};

// The given models: diffuse (albedo / pi, cosine-weighted sampling),
// emission (reflects nothing) and the stand-in of a BSDF whose part is not
// rendered (reflects nothing, as the course's starter code).
extern const BSDFModel kDiffuseModel;
extern const BSDFModel kEmissionModel;
extern const BSDFModel kBlackModel;

// The model used for a material of type t that has none set.
inline const BSDFModel& default_bsdf_model(MaterialType t) {
  switch (t) {
    case MaterialType::Diffuse: return kDiffuseModel;
    case MaterialType::Emission: return kEmissionModel;
    default: return kBlackModel;
  }
}

inline const BSDFModel& bsdf_model(const Material& m) { return m.model ? *m.model : default_bsdf_model(m.type); }

// Diffuse: albedo / pi. As in the course it does not look at the sides of
// wo and wi; the estimators skip light directions below the surface.
inline Color diffuse_f(const Material& m, const Vec3& wo, const Vec3& wi) {
  (void)wo;
  (void)wi;
  return m.albedo * kInvPi;
}

// Diffuse: cosine-weighted about the normal.
inline Color diffuse_sample_f(const Material& m, const Vec3& wo, float u1, float u2, Vec3* wi, float* pdf) {
  *wi = sample_cosine_hemisphere(u1, u2);
  *pdf = cosine_hemisphere_pdf(*wi);
  return diffuse_f(m, wo, *wi);
}

inline float diffuse_pdf(const Material& m, const Vec3& wo, const Vec3& wi) {
  (void)m;
  (void)wo;
  return cosine_hemisphere_pdf(wi);
}

// The material's BSDF value, f(wo, wi). (The diffuse BSDF, by far the
// most common, is called inline rather than through the model's pointer.)
inline Color bsdf_f(const Material& m, const Vec3& wo, const Vec3& wi) {
  const BSDFModel& b = bsdf_model(m);
  return &b == &kDiffuseModel ? diffuse_f(m, wo, wi) : b.f(m, wo, wi);
}

// Samples wi for outgoing wo; returns f and sets *wi and *pdf (see
// BSDFModel::sample_f).
inline Color bsdf_sample_f(const Material& m, const Vec3& wo, float u1, float u2, Vec3* wi, float* pdf) {
  const BSDFModel& b = bsdf_model(m);
  return &b == &kDiffuseModel ? diffuse_sample_f(m, wo, u1, u2, wi, pdf) : b.sample_f(m, wo, u1, u2, wi, pdf);
}

inline float bsdf_pdf(const Material& m, const Vec3& wo, const Vec3& wi) {
  const BSDFModel& b = bsdf_model(m);
  return &b == &kDiffuseModel ? diffuse_pdf(m, wo, wi) : b.pdf(m, wo, wi);
}

// Whether the material's BSDF is a delta distribution (mirror, glass).
inline bool bsdf_is_delta(const Material& m) { return bsdf_model(m).delta; }

inline Color emission(const Material& m) { return m.emission; }

}  // namespace pt
