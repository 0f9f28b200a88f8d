#include "common/bsdf.h"

namespace pt {

namespace {

Color nothing_f(const Material&, const Vec3&, const Vec3&) { return Color(0.0f); }

float nothing_pdf(const Material&, const Vec3&, const Vec3&) { return 0.0f; }

// Emission: a cosine-weighted direction that carries nothing (the path
// ends there, as at any black surface).
Color emission_sample_f(const Material& m, const Vec3& wo, float u1, float u2, Vec3* wi, float* pdf) {
  diffuse_sample_f(m, wo, u1, u2, wi, pdf);
  return Color(0.0f);
}

// A BSDF whose part is not rendered: no direction at all.
Color black_sample_f(const Material&, const Vec3&, float, float, Vec3* wi, float* pdf) {
  *wi = Vec3(0.0f, 0.0f, 1.0f);
  *pdf = 0.0f;
  return Color(0.0f);
}

}  // namespace

const BSDFModel kDiffuseModel = {"diffuse", diffuse_f, diffuse_sample_f, diffuse_pdf, false};
const BSDFModel kEmissionModel = {"emission", nothing_f, emission_sample_f, diffuse_pdf, false};
const BSDFModel kBlackModel = {"not rendered", nothing_f, black_sample_f, nothing_pdf, false};

}  // namespace pt
