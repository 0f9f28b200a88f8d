#include "stages/part7_microfacet/microfacet.h"

#include <cmath>

#include "common/math_constants.h"
#include "common/todo.h"

namespace pt {

float microfacet_Lambda(const Material& m, const Vec3& w) {
  // a = 1 / (alpha tan theta) = cos / (alpha sin), sin theta from w's x
  // and y (1 - cos^2 loses its digits near the normal, where a is
  // infinite and Lambda 0).
  const float a = w.z / (m.alpha * std::sqrt(w.x * w.x + w.y * w.y));
  // Past a = 4, Lambda is below 3e-10, which 1 + Lambda in float cannot
  // show: no masking, and no erf and exp to compute (most directions of a
  // smooth surface).
  if (a > 4.0f) return 0.0f;
  constexpr float kSqrtPi = 1.7724538509f;
  if (!(a > 0.0f)) return 0.5f * (std::erf(a) - 1.0f) + std::exp(-a * a) / (2.0f * a * kSqrtPi);
  // erf(a) - 1 = -erfc(a) = -t P(t) exp(-a^2), t = 1 / (1 + p a), to within
  // 1.5e-7 (Abramowitz and Stegun 7.1.26), which shares exp(-a^2) with the
  // second term: one exp instead of an exp and an erf.
  const float e = std::exp(-a * a), t = 1.0f / (1.0f + 0.3275911f * a);
  const float erfc_over_e =
      t * (0.254829592f + t * (-0.284496736f + t * (1.421413741f + t * (-1.453152027f + t * 1.061405429f))));
  return e * (1.0f / (2.0f * a * kSqrtPi) - 0.5f * erfc_over_e);
}

float microfacet_G(const Material& m, const Vec3& wo, const Vec3& wi) {
  return 1.0f / (1.0f + microfacet_Lambda(m, wi) + microfacet_Lambda(m, wo));
}

float microfacet_D(const Material& m, const Vec3& h) {
  // BEGIN SOLUTION
  // STUB: PT_TODO(7, "D = 1 everywhere");
  // STUB: unused(m, h);
  // STUB: return 1.0f;
  const float c = h.z;
  if (!(c > 0)) return 0.0f;
  const float c2 = c * c, a2 = m.alpha * m.alpha;
  // sin^2 from x and y: 1 - cos^2 loses its digits near the normal.
  const float e = (h.x * h.x + h.y * h.y) / (c2 * a2);
  if (e > 80.0f) return 0.0f;  // below 1e-30 for alpha <= 1; spares exp's slow underflow
  return std::exp(-e) / (kPi * a2 * c2 * c2);
  // END SOLUTION
}

Color microfacet_F(const Material& m, const Vec3& wi) {
  // BEGIN SOLUTION
  // STUB: PT_TODO(7, "F = 0: metal reflects nothing");
  // STUB: unused(m, wi);
  // STUB: return Color(0.0f);
  const float c = wi.z > 0.0f ? (wi.z < 1.0f ? wi.z : 1.0f) : 0.0f, c2 = c * c;
  Color F;
  for (int i = 0; i < 3; ++i) {
    // Rs = (A - B) / (A + B), Rp = (C - B) / (C + B) with A = eta^2 + k^2 +
    // cos^2, B = 2 eta cos, C = (eta^2 + k^2) cos^2 + 1; their mean is
    // (A C - B^2) / ((A + B)(C + B)), one division instead of two.
    const float eta = m.eta[i], a = eta * eta + m.k[i] * m.k[i];
    const float A = a + c2, B = 2.0f * eta * c, C = a * c2 + 1.0f;
    F[i] = (A * C - B * B) / ((A + B) * (C + B));
  }
  return F;
  // END SOLUTION
}

Color microfacet_f(const Material& m, const Vec3& wo, const Vec3& wi) {
  // BEGIN SOLUTION
  // STUB: PT_TODO(7, "metal reflects nothing: black");
  // STUB: unused(m, wo, wi);
  // STUB: return Color(0.0f);
  if (!(wo.z > 0) || !(wi.z > 0)) return Color(0.0f);
  const float D = microfacet_D(m, normalize(wo + wi));
  if (D == 0.0f) return Color(0.0f);  // far from the lobe: F and G need not be computed
  return microfacet_F(m, wi) * (microfacet_G(m, wo, wi) * D / (4.0f * wo.z * wi.z));
  // END SOLUTION
}

Color microfacet_sample_f(const Material& m, const Vec3& wo, float u1, float u2, Vec3* wi, float* pdf) {
  // BEGIN SOLUTION
  // STUB: PT_TODO(7, "cosine-weighted directions, f of microfacet_f");
  // STUB: *wi = sample_cosine_hemisphere(u1, u2);
  // STUB: *pdf = cosine_hemisphere_pdf(*wi);
  // STUB: return microfacet_f(m, wo, *wi);
  // tan^2 theta_h = -alpha^2 ln(1 - u1); 1 - u1 > 0 since u1 < 1.
  const float tan2 = -m.alpha * m.alpha * std::log(1.0f - u1);
  const float cos_h = 1.0f / std::sqrt(1.0f + tan2);
  const float sin_h = std::sqrt(tan2) * cos_h;
  const float phi = 2.0f * kPi * u2;
  const Vec3 h(sin_h * std::cos(phi), sin_h * std::sin(phi), cos_h);
  *wi = h * (2.0f * dot(wo, h)) - wo;
  if (!(wo.z > 0) || !(wi->z > 0)) {
    *pdf = 0.0f;
    return Color(0.0f);
  }
  // microfacet_pdf and microfacet_f, sharing their half vector and D.
  const Vec3 hw = normalize(wo + *wi);
  const float D = microfacet_D(m, hw);
  *pdf = D * hw.z / (4.0f * std::fabs(dot(*wi, hw)));
  if (D == 0.0f) return Color(0.0f);
  return microfacet_F(m, *wi) * (microfacet_G(m, wo, *wi) * D / (4.0f * wo.z * wi->z));
  // END SOLUTION
}

float microfacet_pdf(const Material& m, const Vec3& wo, const Vec3& wi) {
  // BEGIN SOLUTION
  // STUB: PT_TODO(7, "the cosine-weighted density");
  // STUB: unused(m, wo);
  // STUB: return cosine_hemisphere_pdf(wi);
  if (!(wo.z > 0) || !(wi.z > 0)) return 0.0f;
  const Vec3 h = normalize(wo + wi);
  return microfacet_D(m, h) * h.z / (4.0f * std::fabs(dot(wi, h)));
  // END SOLUTION
}

const BSDFModel kMicrofacetModel = {"microfacet", microfacet_f, microfacet_sample_f, microfacet_pdf, false};

Color microfacet_sample_f_cosine(const Material& m, const Vec3& wo, float u1, float u2, Vec3* wi, float* pdf) {
  *wi = sample_cosine_hemisphere(u1, u2);
  *pdf = cosine_hemisphere_pdf(*wi);
  return microfacet_f(m, wo, *wi);
}

float microfacet_pdf_cosine(const Material& m, const Vec3& wo, const Vec3& wi) {
  unused(m, wo);
  return cosine_hemisphere_pdf(wi);
}

const BSDFModel kMicrofacetCosineModel = {"microfacet, cosine-sampled", microfacet_f, microfacet_sample_f_cosine,
                                          microfacet_pdf_cosine, false};

}  // namespace pt
