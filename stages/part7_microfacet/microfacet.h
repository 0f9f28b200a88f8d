// Part 7: the microfacet BRDF of a rough conductor (metal): a surface of
// tiny mirror facets whose normals follow Beckmann's distribution, with
// the conductor's Fresnel reflectance, and sampled by its facet normals.
//
// Directions are local (z = the surface normal), unit, and point away
// from the surface. The material's alpha is Beckmann's roughness (the RMS
// slope of the facets), eta and k the metal's index of refraction and
// extinction coefficient per colour channel.
#pragma once
#include "common/bsdf.h"

namespace pt {

// Beckmann's normal distribution at half vector h (unit, local):
// D(h) = exp(-tan^2(theta_h) / alpha^2) / (pi alpha^2 cos^4(theta_h)) for
// h.z > 0, else 0.
float microfacet_D(const Material& m, const Vec3& h);

// The Fresnel reflectance of air on a conductor of index eta and
// extinction k (per channel), for light along wi, with cos theta = wi.z (the
// angle to the surface normal, as the course defines it):
// Rs = ((eta^2 + k^2) - 2 eta cos + cos^2) / ((eta^2 + k^2) + 2 eta cos + cos^2),
// Rp = ((eta^2 + k^2) cos^2 - 2 eta cos + 1) / ((eta^2 + k^2) cos^2 + 2 eta cos + 1),
// F = (Rs + Rp) / 2.
Color microfacet_F(const Material& m, const Vec3& wi);

// The shadowing-masking term (given), the course's: G = 1 / (1 + Lambda(wi)
// + Lambda(wo)), with Smith's Lambda for Beckmann's distribution,
// Lambda(w) = (erf(a) - 1) / 2 + exp(-a^2) / (2 a sqrt(pi)), a = 1 / (alpha
// tan theta). (The course's code divides by a pi instead of a sqrt(pi),
// which makes Lambda too small and a rough surface reflect more light than
// it receives at grazing angles; see docs/differences.md.)
float microfacet_Lambda(const Material& m, const Vec3& w);
float microfacet_G(const Material& m, const Vec3& wo, const Vec3& wi);

// The BRDF: F(wi) G(wo, wi) D(h) / (4 cos theta_o cos theta_i) with
// h = normalize(wo + wi); 0 unless both wo and wi are above the surface.
Color microfacet_f(const Material& m, const Vec3& wo, const Vec3& wi);

// Importance sampling of Beckmann's distribution: the half vector h at
// theta_h = atan(sqrt(-alpha^2 ln(1 - u1))), phi_h = 2 pi u2 (density
// D(h) cos theta_h per unit solid angle of h), and wi = wo reflected
// about h. The density of wi is that of h divided by 4 |wi . h| (the
// Jacobian of the reflection). A wi at or below the surface is no sample:
// *pdf = 0. Returns f(wo, wi).
Color microfacet_sample_f(const Material& m, const Vec3& wo, float u1, float u2, Vec3* wi, float* pdf);

// The density microfacet_sample_f draws wi with, for wo and wi above the
// surface (else 0): D(h) cos theta_h / (4 |wi . h|).
float microfacet_pdf(const Material& m, const Vec3& wo, const Vec3& wi);

// The model the render gives microfacet materials from part 7 on.
extern const BSDFModel kMicrofacetModel;

// Given: the baseline of the write-up's comparison of samplers
// (--bsdf-hemisphere): the same BRDF, microfacet_f, with wi drawn
// cosine-weighted over the hemisphere (pdf cos theta_i / pi), as the
// course's starter sample_f draws it. Unbiased, and noisier the smoother
// the metal: few such directions fall in a narrow lobe.
Color microfacet_sample_f_cosine(const Material& m, const Vec3& wo, float u1, float u2, Vec3* wi, float* pdf);
float microfacet_pdf_cosine(const Material& m, const Vec3& wo, const Vec3& wi);
extern const BSDFModel kMicrofacetCosineModel;

}  // namespace pt
