#include "stages/part6_mirror_glass/specular.h"

#include <cmath>

#include "common/todo.h"

namespace pt {

namespace {

// f and pdf of a delta BSDF: zero for any pair of directions (the one
// direction it scatters to has no density).
Color specular_f(const Material&, const Vec3&, const Vec3&) { return Color(0.0f); }
float specular_pdf(const Material&, const Vec3&, const Vec3&) { return 0.0f; }

}  // namespace

void reflect(const Vec3& wo, Vec3* wi) {
  // BEGIN SOLUTION
  // STUB: PT_TODO(6, "the reflection is the normal");
  // STUB: unused(wo);
  // STUB: *wi = Vec3(0.0f, 0.0f, 1.0f);
  *wi = Vec3(-wo.x, -wo.y, wo.z);
  // END SOLUTION
}

bool refract(const Vec3& wo, Vec3* wi, float ior) {
  // BEGIN SOLUTION
  // STUB: PT_TODO(6, "no refraction ever (as total internal reflection)");
  // STUB: unused(wo, wi, ior);
  // STUB: return false;
  const bool entering = wo.z > 0;
  const float eta = entering ? 1.0f / ior : ior;
  const float cos2 = 1.0f - eta * eta * (1.0f - wo.z * wo.z);
  if (!(cos2 > 0)) return false;  // total internal reflection
  const float cos_i = std::sqrt(cos2);
  *wi = Vec3(-eta * wo.x, -eta * wo.y, entering ? -cos_i : cos_i);
  return true;
  // END SOLUTION
}

float schlick_reflectance(float cos_theta, float ior) {
  // BEGIN SOLUTION
  // STUB: PT_TODO(6, "reflectance 0");
  // STUB: unused(cos_theta, ior);
  // STUB: return 0.0f;
  const float r = (1.0f - ior) / (1.0f + ior);
  const float r0 = r * r;
  const float c = 1.0f - cos_theta;
  return r0 + (1.0f - r0) * (c * c) * (c * c) * c;
  // END SOLUTION
}

Color mirror_sample_f(const Material& m, const Vec3& wo, float u1, float u2, Vec3* wi, float* pdf) {
  // BEGIN SOLUTION
  // STUB: PT_TODO(6, "mirrors reflect nothing: black");
  // STUB: unused(m, wo, u1, u2);
  // STUB: *wi = Vec3(0.0f, 0.0f, 1.0f);
  // STUB: *pdf = 0.0f;
  // STUB: return Color(0.0f);
  (void)u1;
  (void)u2;
  reflect(wo, wi);
  const float c = std::fabs(wi->z);
  *pdf = c > 0 ? 1.0f : 0.0f;  // a grazing direction carries nothing
  return c > 0 ? m.reflectance / c : Color(0.0f);
  // END SOLUTION
}

Color refraction_sample_f(const Material& m, const Vec3& wo, float u1, float u2, Vec3* wi, float* pdf) {
  // BEGIN SOLUTION
  // STUB: PT_TODO(6, "refracting surfaces send nothing: black");
  // STUB: unused(m, wo, u1, u2);
  // STUB: *wi = Vec3(0.0f, 0.0f, 1.0f);
  // STUB: *pdf = 0.0f;
  // STUB: return Color(0.0f);
  (void)u1;
  (void)u2;
  *pdf = 0.0f;
  if (!refract(wo, wi, m.ior)) return Color(0.0f);
  const float eta = wo.z > 0 ? 1.0f / m.ior : m.ior;
  const float c = std::fabs(wi->z);
  if (!(c > 0)) return Color(0.0f);
  *pdf = 1.0f;
  return m.transmittance * (eta * eta / c);
  // END SOLUTION
}

Color glass_sample_f(const Material& m, const Vec3& wo, float u1, float u2, Vec3* wi, float* pdf) {
  // BEGIN SOLUTION
  // STUB: PT_TODO(6, "glass sends nothing: black");
  // STUB: unused(m, wo, u1, u2);
  // STUB: *wi = Vec3(0.0f, 0.0f, 1.0f);
  // STUB: *pdf = 0.0f;
  // STUB: return Color(0.0f);
  (void)u2;
  Vec3 refracted;
  if (!refract(wo, &refracted, m.ior)) {  // total internal reflection
    reflect(wo, wi);
    const float c = std::fabs(wi->z);
    *pdf = c > 0 ? 1.0f : 0.0f;
    return c > 0 ? m.reflectance / c : Color(0.0f);
  }
  // Schlick's formula wants the angle on the air side, which for light
  // leaving the glass is the refracted direction's.
  const float cos_air = wo.z > 0 ? wo.z : std::fabs(refracted.z);
  const float R = schlick_reflectance(cos_air, m.ior);
  if (u1 < R) {
    reflect(wo, wi);
    *pdf = R;
    return m.reflectance * (R / std::fabs(wi->z));
  }
  *wi = refracted;
  const float eta = wo.z > 0 ? 1.0f / m.ior : m.ior;
  *pdf = 1.0f - R;
  return m.transmittance * ((1.0f - R) * eta * eta / std::fabs(wi->z));
  // END SOLUTION
}

const BSDFModel kMirrorModel = {"mirror", specular_f, mirror_sample_f, specular_pdf, true};
const BSDFModel kRefractionModel = {"refraction", specular_f, refraction_sample_f, specular_pdf, true};
const BSDFModel kGlassModel = {"glass", specular_f, glass_sample_f, specular_pdf, true};

}  // namespace pt
