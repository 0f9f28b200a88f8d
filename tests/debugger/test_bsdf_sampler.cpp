// The BSDF sampler (viewer/debugger): it reports what the build's sample_f
// returns, its histogram of the directions drawn agrees with the pdf the
// BSDF reports when the two belong together and flags them when they do
// not, and a delta BSDF gives its one or two directions with the Fresnel
// split.
//
// Statistics: each histogram is judged bin by bin (|z| <= 4.5, Bonferroni
// over at most 61 tests: a correct sampler is flagged with probability at
// most 4.2e-4 per run). The runs are seeded (seeds 1 to 3) and run once each:
// 12 histograms of correct samplers and 3 glass splits (two directions
// each, |z| <= 4.5), so a correct build fails this file with probability
// about 0.5%, and the same way every time for a given build.
//
// Deliberate bugs (planted in a scratch copy) -> tests here that failed:
//   the expected counts integrated without sin theta (dtheta dphi)
//                                       -> correct samplers agree
//   every delta direction given the first sample's pdf
//                                       -> glass: the Fresnel split
//   delta directions not grouped by their bits (one group per sample)
//                                       -> mirror: one direction; glass: two
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <string>

#include "common/bsdf.h"
#include "common/math_constants.h"
#include "stages/part6_mirror_glass/specular.h"
#include "stages/part7_microfacet/microfacet.h"
#include "viewer/debugger/debugger.h"

using namespace pt;

namespace {

Material microfacet(float alpha, const BSDFModel* model = &kMicrofacetModel) {
  Material m;
  m.name = "metal";
  m.type = MaterialType::Microfacet;
  m.alpha = alpha;
  m.eta = Color(0.2f, 0.9f, 1.1f);
  m.k = Color(3.9f, 2.4f, 2.2f);
  m.model = model;
  return m;
}

Material with_model(MaterialType type, const BSDFModel* model) {
  Material m;
  m.type = type;
  m.model = model;
  return m;
}

// wo at `degrees` from the normal (0, 0, 1), in the x-z plane.
Vec3 wo_at(double degrees) {
  const double t = degrees * kPiDouble / 180;
  return Vec3(float(std::sin(t)), 0.0f, float(std::cos(t)));
}

const Vec3 kPoint(0, 0, 0), kNormal(0, 0, 1);

// Planted bugs of a student's part 7, as whole models.
// (1) The half vector drawn with alpha instead of alpha^2 in tan^2 theta_h,
// the pdf right: the directions do not follow the pdf.
Color wrong_alpha_sample_f(const Material& m, const Vec3& wo, float u1, float u2, Vec3* wi, float* pdf) {
  const float tan2 = -m.alpha * std::log(1.0f - u1);
  const float cos_h = 1.0f / std::sqrt(1.0f + tan2), sin_h = std::sqrt(tan2) * cos_h, phi = 2.0f * kPi * u2;
  const Vec3 h(sin_h * std::cos(phi), sin_h * std::sin(phi), cos_h);
  *wi = h * (2.0f * dot(wo, h)) - wo;
  *pdf = microfacet_pdf(m, wo, *wi);
  return *pdf > 0 ? microfacet_f(m, wo, *wi) : Color(0.0f);
}
const BSDFModel kWrongAlphaModel = {"microfacet", microfacet_f, wrong_alpha_sample_f, microfacet_pdf, false};

// (2) The pdf of the half vector taken for wi's (no 1 / (4 |wi . h|)).
float half_vector_pdf(const Material& m, const Vec3& wo, const Vec3& wi) {
  if (!(wo.z > 0) || !(wi.z > 0)) return 0.0f;
  const Vec3 h = normalize(wo + wi);
  return microfacet_D(m, h) * h.z;
}
Color half_vector_sample_f(const Material& m, const Vec3& wo, float u1, float u2, Vec3* wi, float* pdf) {
  const Color f = microfacet_sample_f(m, wo, u1, u2, wi, pdf);
  if (*pdf > 0) *pdf = half_vector_pdf(m, wo, *wi);
  return f;
}
const BSDFModel kHalfVectorPdfModel = {"microfacet", microfacet_f, half_vector_sample_f, half_vector_pdf, false};

int histogram_total(const debug::BsdfSamplesResult& r) {
  int total = r.no_direction;
  for (const debug::BsdfHistogramBin& b : r.histogram) total += b.count;
  return total;
}

}  // namespace

TEST_CASE("the BSDF sampler reports exactly what sample_f returns", "[debugger][part7]") {
  const Material m = microfacet(0.25f);
  const debug::BsdfSamplesResult r = debug::sample_bsdf_many(m, kPoint, kNormal, wo_at(30), 64, 5);
  REQUIRE(r.ok());
  CHECK(r.model == std::string("microfacet"));
  CHECK_FALSE(r.delta);
  REQUIRE(r.samples.size() == 64);
  for (const debug::BsdfSampleTest& s : r.samples) {
    Vec3 wi;
    float pdf = 0;
    const Color f = bsdf_sample_f(m, r.wo_local, s.u1, s.u2, &wi, &pdf);
    CHECK(wi.x == s.wi_local.x);
    CHECK(wi.y == s.wi_local.y);
    CHECK(wi.z == s.wi_local.z);
    CHECK(pdf == s.pdf);
    CHECK(f.x == s.f.x);
  }
  CHECK(histogram_total(r) == 64);
  CHECK(r.pdf_mismatches == 0);
}

TEST_CASE("the histogram agrees with the pdf of correct samplers (seeded, alpha 4.2e-4 per run)",
          "[debugger][part7][statistics]") {
  struct Case {
    Material m;
    double wo_degrees;
    uint64_t seed;
    const char* what;
  };
  const Material diffuse = with_model(MaterialType::Diffuse, nullptr);
  const Case cases[] = {
      {diffuse, 0, 1, "diffuse, wo along the normal"},
      {diffuse, 60, 2, "diffuse, wo at 60 degrees"},
      {microfacet(0.05f), 0, 1, "microfacet alpha 0.05, wo along the normal"},
      {microfacet(0.05f), 45, 2, "microfacet alpha 0.05, wo at 45 degrees"},
      {microfacet(0.25f), 30, 1, "microfacet alpha 0.25, wo at 30 degrees"},
      {microfacet(0.25f), 75, 3, "microfacet alpha 0.25, wo at 75 degrees (some directions below the surface)"},
      {microfacet(0.5f), 10, 1, "microfacet alpha 0.5, wo at 10 degrees"},
      {microfacet(0.5f), 85, 2, "microfacet alpha 0.5, wo at 85 degrees"},
      {microfacet(0.5f, &kMicrofacetCosineModel), 40, 1, "cosine-sampled microfacet (--bsdf-hemisphere)"},
      {microfacet(0.25f, &kMicrofacetCosineModel), 70, 2, "cosine-sampled microfacet at 70 degrees"},
      {microfacet(0.1f), 20, 3, "microfacet alpha 0.1, wo at 20 degrees"},
      {microfacet(0.1f), 60, 1, "microfacet alpha 0.1, wo at 60 degrees"},
  };
  for (const Case& c : cases) {
    const debug::BsdfSamplesResult r = debug::sample_bsdf_many(c.m, kPoint, kNormal, wo_at(c.wo_degrees), 4096, c.seed);
    INFO(c.what << ": " << r.verdict);
    REQUIRE(r.ok());
    CHECK(r.agrees);
    CHECK(r.histogram.size() == 30);  // nothing below the surface: 0-90 degrees
    CHECK(histogram_total(r) == 4096);
    CHECK(r.pdf_mismatches == 0);
    // No direction (pdf 0) has the probability the pdf leaves out; the
    // grid's integral is within 5e-4 of the pdf's (2 samples in 4096).
    const double none = std::max(0.0, 1 - r.pdf_integral);
    CHECK(std::fabs(r.no_direction - 4096 * none) <= 4.5 * std::sqrt(4096 * none * (1 - none)) + 4096 * 5e-4);
    CHECK(r.pdf_integral <= 1 + 5e-4);
    int judged = 0;
    for (const debug::BsdfHistogramBin& b : r.histogram) judged += b.judged ? 1 : 0;
    CHECK(judged >= 4);  // the test looked at something
  }
}

TEST_CASE("the histogram flags a sampler whose directions do not follow its pdf", "[debugger][part7][statistics]") {
  // Drawn with alpha for alpha^2: too wide a lobe for the pdf reported.
  const debug::BsdfSamplesResult wide =
      debug::sample_bsdf_many(microfacet(0.1f, &kWrongAlphaModel), kPoint, kNormal, wo_at(30), 4096, 1);
  INFO(wide.verdict);
  CHECK_FALSE(wide.agrees);
  CHECK(wide.verdict.find("do not follow") != std::string::npos);
  // The half vector's density for wi's: the pdf integrates to far from 1.
  const debug::BsdfSamplesResult half =
      debug::sample_bsdf_many(microfacet(0.25f, &kHalfVectorPdfModel), kPoint, kNormal, wo_at(30), 4096, 1);
  INFO(half.verdict);
  CHECK_FALSE(half.agrees);
  CHECK(half.pdf_integral > 1.5);
}

TEST_CASE("a mirror gives one direction, wo mirrored about the normal, every time", "[debugger][part6]") {
  const Material mirror = with_model(MaterialType::Mirror, &kMirrorModel);
  const debug::BsdfSamplesResult r = debug::sample_bsdf_many(mirror, kPoint, Vec3(0, 2, 0), Vec3(1, 1, 0.5f), 500, 1);
  REQUIRE(r.ok());
  CHECK(r.delta);
  CHECK(r.histogram.empty());
  REQUIRE(r.directions.size() == 1);
  const debug::BsdfDirection& d = r.directions[0];
  CHECK(d.scatter == "reflected");
  CHECK(d.count == 500);
  CHECK(d.pdf == 1.0f);
  CHECK(d.mirror_error <= 1e-6f);
  CHECK(r.normal.y == 1.0f);  // normalised
  // In the world: the reflection of wo about the normal (0, 1, 0).
  const Vec3 wo = normalize(Vec3(1, 1, 0.5f));
  CHECK(std::fabs(d.wi.x + wo.x) <= 1e-6f);
  CHECK(std::fabs(d.wi.y - wo.y) <= 1e-6f);
  CHECK(std::fabs(d.wi.z + wo.z) <= 1e-6f);
  CHECK(r.agrees);
}

TEST_CASE("glass gives its reflection and refraction, chosen with the Fresnel split it reports", "[debugger][part6]") {
  Material glass = with_model(MaterialType::Glass, &kGlassModel);
  glass.ior = 1.5f;
  for (double degrees : {0.0, 40.0, 75.0}) {
    const Vec3 wo = wo_at(degrees);
    const debug::BsdfSamplesResult r = debug::sample_bsdf_many(glass, kPoint, kNormal, wo, 4096, 2);
    INFO(degrees << " degrees: " << r.verdict);
    REQUIRE(r.ok());
    REQUIRE(r.directions.size() == 2);
    CHECK(r.agrees);
    const debug::BsdfDirection& a = r.directions[0];
    const debug::BsdfDirection& b = r.directions[1];
    const debug::BsdfDirection& refl = a.scatter == "reflected" ? a : b;
    const debug::BsdfDirection& refr = a.scatter == "reflected" ? b : a;
    REQUIRE(refl.scatter == "reflected");
    REQUIRE(refr.scatter == "refracted");
    CHECK(refl.count + refr.count == 4096);
    // The probabilities reported are Schlick's R and 1 - R.
    const float R = schlick_reflectance(float(wo.z), 1.5f);
    CHECK(std::fabs(refl.pdf - R) <= 1e-6f);
    CHECK(std::fabs(refr.pdf - (1 - R)) <= 1e-6f);
    // The counts follow them (|z| <= 4.5; three seeded runs).
    CHECK(std::fabs(refl.count - 4096.0 * R) <= 4.5 * std::sqrt(4096.0 * R * (1 - R)));
    CHECK(refl.mirror_error <= 1e-6f);
    // Snell's law from air into glass: sin theta_o / sin theta_i = 1.5.
    if (degrees > 0) CHECK(std::fabs(refr.sine_ratio - 1.5f) <= 1e-4f);
    CHECK(refr.wi_local.z < 0);
  }
  // From inside beyond the critical angle (41.8 degrees): total internal
  // reflection, one direction, always.
  const Vec3 inside = Vec3(std::sin(1.2f), 0, -std::cos(1.2f));
  const debug::BsdfSamplesResult tir = debug::sample_bsdf_many(glass, kPoint, kNormal, inside, 300, 1);
  REQUIRE(tir.directions.size() == 1);
  CHECK(tir.directions[0].scatter == "reflected");
  CHECK(tir.directions[0].count == 300);
}

TEST_CASE("the BSDF sampler refuses absurd input with a one-line InputError", "[debugger]") {
  const Material m = microfacet(0.25f);
  using debug::InputError;
  CHECK_THROWS_AS(debug::sample_bsdf_many(m, kPoint, kNormal, wo_at(10), 0, 1), InputError);
  CHECK_THROWS_AS(debug::sample_bsdf_many(m, kPoint, kNormal, wo_at(10), debug::kMaxBsdfSamples + 1, 1), InputError);
  CHECK_THROWS_AS(debug::sample_bsdf_many(m, kPoint, Vec3(0, 0, 0), wo_at(10), 8, 1), InputError);
  CHECK_THROWS_AS(debug::sample_bsdf_many(m, kPoint, kNormal, Vec3(0, NAN, 1), 8, 1), InputError);
  try {
    debug::sample_bsdf_many(m, kPoint, kNormal, wo_at(10), 0, 1);
  } catch (const InputError& e) {
    CHECK(std::string(e.what()).find('\n') == std::string::npos);
    CHECK(std::string(e.what()).find("number of samples") != std::string::npos);
  }
}
