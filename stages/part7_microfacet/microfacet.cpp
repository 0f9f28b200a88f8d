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
  constexpr float kSqrtPi = 1.7724538509f;
  return 0.5f * (std::erf(a) - 1.0f) + std::exp(-a * a) / (2.0f * a * kSqrtPi);
}

float microfacet_G(const Material& m, const Vec3& wo, const Vec3& wi) {
  return 1.0f / (1.0f + microfacet_Lambda(m, wi) + microfacet_Lambda(m, wo));
}

float microfacet_D(const Material& m, const Vec3& h) {
  // BEGIN SOLUTION
  // STUB: PT_TODO(7);
  // STUB: unused(m, h);
  // STUB: return 1.0f;
  const float c = h.z;
  if (!(c > 0)) return 0.0f;
  const float c2 = c * c, a2 = m.alpha * m.alpha;
  // sin^2 from x and y: 1 - cos^2 loses its digits near the normal.
  const float tan2 = (h.x * h.x + h.y * h.y) / c2;
  return std::exp(-tan2 / a2) / (kPi * a2 * c2 * c2);
  // END SOLUTION
}

Color microfacet_F(const Material& m, const Vec3& wi) {
  // BEGIN SOLUTION
  // STUB: PT_TODO(7);
  // STUB: unused(m, wi);
  // STUB: return Color(0.0f);
  const float c = std::fmin(std::fmax(wi.z, 0.0f), 1.0f), c2 = c * c;
  Color F;
  for (int i = 0; i < 3; ++i) {
    const float eta = m.eta[i], a = eta * eta + m.k[i] * m.k[i];
    const float rs = (a - 2.0f * eta * c + c2) / (a + 2.0f * eta * c + c2);
    const float rp = (a * c2 - 2.0f * eta * c + 1.0f) / (a * c2 + 2.0f * eta * c + 1.0f);
    F[i] = 0.5f * (rs + rp);
  }
  return F;
  // END SOLUTION
}

Color microfacet_f(const Material& m, const Vec3& wo, const Vec3& wi) {
  // BEGIN SOLUTION
  // STUB: PT_TODO(7);
  // STUB: unused(m, wo, wi);
  // STUB: return Color(0.0f);
  if (!(wo.z > 0) || !(wi.z > 0)) return Color(0.0f);
  const Vec3 h = normalize(wo + wi);
  return microfacet_F(m, wi) * (microfacet_G(m, wo, wi) * microfacet_D(m, h) / (4.0f * wo.z * wi.z));
  // END SOLUTION
}

Color microfacet_sample_f(const Material& m, const Vec3& wo, float u1, float u2, Vec3* wi, float* pdf) {
  // BEGIN SOLUTION
  // STUB: PT_TODO(7);
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
  *pdf = microfacet_pdf(m, wo, *wi);
  return microfacet_f(m, wo, *wi);
  // END SOLUTION
}

float microfacet_pdf(const Material& m, const Vec3& wo, const Vec3& wi) {
  // BEGIN SOLUTION
  // STUB: PT_TODO(7);
  // STUB: unused(m, wo);
  // STUB: return cosine_hemisphere_pdf(wi);
  if (!(wo.z > 0) || !(wi.z > 0)) return 0.0f;
  const Vec3 h = normalize(wo + wi);
  return microfacet_D(m, h) * h.z / (4.0f * std::fabs(dot(wi, h)));
  // END SOLUTION
}

const BSDFModel kMicrofacetModel = {"microfacet", microfacet_f, microfacet_sample_f, microfacet_pdf, false};

}  // namespace pt
