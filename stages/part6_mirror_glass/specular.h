// Part 6: perfectly specular surfaces: the mirror, the refracting surface
// and glass, which reflects or refracts as Fresnel's reflectance says.
//
// Directions are local (z = the surface normal, which points out of the
// glass), unit, and point away from the surface: wo toward where the light
// goes, wi toward where it comes from.
#pragma once
#include "common/bsdf.h"

namespace pt {

// Sets *wi to wo reflected about the normal (0, 0, 1).
void reflect(const Vec3& wo, Vec3* wi);

// Refracts wo through the surface of a medium of index `ior` by Snell's
// law (air outside, index 1). wo.z > 0: wo is outside, and *wi goes inside
// (eta = 1 / ior); otherwise wo is inside and *wi goes out (eta = ior).
// Then *wi = (-eta wo.x, -eta wo.y, -/+ sqrt(1 - eta^2 (1 - wo.z^2))), on
// the other side of the surface from wo. Returns false, leaving *wi as it
// was, when there is no refracted direction (total internal reflection:
// 1 - eta^2 (1 - wo.z^2) <= 0).
bool refract(const Vec3& wo, Vec3* wi, float ior);

// Schlick's approximation of the Fresnel reflectance of an interface
// between air and a medium of index `ior`, for light meeting it at an angle
// whose cosine, measured on the air side, is cos_theta:
// R0 + (1 - R0) (1 - cos_theta)^5 with R0 = ((1 - ior) / (1 + ior))^2.
float schlick_reflectance(float cos_theta, float ior);

// The BSDFs' sample_f (see BSDFModel::sample_f in common/bsdf.h). Each
// returns the single direction it scatters to, *pdf the probability of
// having chosen it, and f such that f |cos theta_i| / pdf is the sample's
// weight; *pdf = 0 when it sends nothing.
//
// Mirror: wi = reflect(wo), pdf 1, f = reflectance / |cos theta_i|.
Color mirror_sample_f(const Material& m, const Vec3& wo, float u1, float u2, Vec3* wi, float* pdf);

// Refraction only: wi = refract(wo), pdf 1, f = transmittance eta^2 /
// |cos theta_i| (radiance crossing into a medium of another index is
// scaled by the square of the indices' ratio, eta^2 = (n on wo's side /
// n on wi's side)^2). At total internal reflection nothing (pdf 0).
Color refraction_sample_f(const Material& m, const Vec3& wo, float u1, float u2, Vec3* wi, float* pdf);

// Glass: at total internal reflection, the mirror's reflection with the
// glass's reflectance (pdf 1). Otherwise R = schlick_reflectance(cos,
// ior), cos taken on the air side (|wo.z| if wo is outside, else |cos| of
// the refracted direction); with u1 < R the reflection (pdf R, f = R
// reflectance / |cos theta_i|), else the refraction (pdf 1 - R, f = (1 - R)
// transmittance eta^2 / |cos theta_i|).
Color glass_sample_f(const Material& m, const Vec3& wo, float u1, float u2, Vec3* wi, float* pdf);

// The models the render gives mirror, refraction and glass materials from
// part 6 on: delta BSDFs, whose f and pdf are 0 for any pair of directions.
extern const BSDFModel kMirrorModel;
extern const BSDFModel kRefractionModel;
extern const BSDFModel kGlassModel;

}  // namespace pt
