// Part 6: reflection, refraction and the mirror, refraction and glass
// BSDFs, against closed forms computed here in double precision.
//
// Statistics: chi-square goodness of fit of glass's choice between
// reflection and refraction (two cells: the counts of each against the
// probabilities of Schlick's formula computed here), family-wise alpha =
// 0.01 over the K = 10 tests of this file (Sidak: each at 1 - 0.99^(1/10) =
// 0.001005), 200,000 samples each, fixed seeds: light arriving from outside
// at 0, 45, 80 and 89.5 degrees and from inside at 0, 30, 43 and 60 degrees
// (43.6 is the critical angle at ior 1.45; 60 is total internal
// reflection), and at ior 2.4 from outside at 70 and from inside at 24
// degrees (critical 24.6). The other checks are exact per sample.
//
// Deliberate bug (planted in a scratch copy) -> tests here that failed on it
// (tests/part6/test_delta_paths.cpp's in brackets):
//   refract: wi.z on the same side as wo             -> Snell's law, glass chi-square, white glass,
//                                                       reciprocity, refraction [glass sphere]
//   refract: eta = ior entering (1 / ior leaving)    -> Snell's law, glass chi-square, refraction
//   refract: no total internal reflection check      -> Snell's law, glass chi-square, white glass
//   refract: wi's x and y not negated                -> Snell's law
//   reflect: z negated instead of x and y            -> reflect, mirror weight, glass chi-square,
//                                                       white glass [mirror and glass spheres]
//   Schlick with the inside angle for exiting light  -> glass chi-square, reciprocity
//   glass: pdf 1 for the chosen reflection (not R)   -> glass chi-square, white glass [glass sphere]
//   glass: reflects when u1 >= R (branches swapped)  -> glass chi-square [glass sphere]
//   glass: refraction without eta^2, or with 1/eta^2 -> glass chi-square (weights), white glass
//   refraction: weight without eta^2                 -> refraction
//   mirror: f = reflectance (no division by cos)     -> mirror weight [mirror sphere, emission]
#include <catch2/catch.hpp>
#include <cmath>
#include <sstream>
#include <vector>

#include "common/rng.h"
#include "stages/part6_mirror_glass/specular.h"
#include "tests/statistics/hypothesis_tests.h"
#include "tests/statistics/special_functions.h"

using namespace pt;
using namespace pt::test;

namespace {

constexpr double kAlpha = 0.01;
constexpr int kChiSquareTests = 10;
constexpr int kSamples = 200000;
const double kAlphaEach = sidak(kAlpha, kChiSquareTests);

Material glass(float ior, const Color& reflectance = Color(1.0f), const Color& transmittance = Color(1.0f)) {
  Material m;
  m.type = MaterialType::Glass;
  m.ior = ior;
  m.reflectance = reflectance;
  m.transmittance = transmittance;
  return m;
}

// The direction at `deg` degrees from the normal, on the outside (+z) or
// the inside (-z), turned by azimuth phi.
Vec3 at_angle(double deg, bool inside, double phi = 0.7) {
  const double t = deg * M_PI / 180.0;
  return Vec3(float(std::sin(t) * std::cos(phi)), float(std::sin(t) * std::sin(phi)),
              float(inside ? -std::cos(t) : std::cos(t)));
}

// Snell's law in double: the refracted direction's cosine (positive) for
// wo, or -1 at total internal reflection.
double refracted_cos(const Vec3& wo, double ior) {
  const double eta = wo.z > 0 ? 1.0 / ior : ior;
  const double c2 = 1.0 - eta * eta * (1.0 - double(wo.z) * wo.z);
  return c2 > 0 ? std::sqrt(c2) : -1.0;
}

// Schlick's reflectance with the cosine on the air side, in double.
double expected_reflectance(const Vec3& wo, double ior) {
  const double ct = refracted_cos(wo, ior);
  if (ct < 0) return 1.0;
  const double cos_air = wo.z > 0 ? wo.z : ct;
  const double r0 = ((1 - ior) / (1 + ior)) * ((1 - ior) / (1 + ior));
  return r0 + (1 - r0) * std::pow(1 - cos_air, 5);
}

double sin_theta(const Vec3& w) { return std::hypot(double(w.x), double(w.y)); }

}  // namespace

TEST_CASE("reflect mirrors wo about the normal", "[part6][specular]") {
  Rng rng(61);
  for (int i = 0; i < 1000; ++i) {
    const Vec3 wo = normalize(Vec3(rng.uniform() * 2 - 1, rng.uniform() * 2 - 1, rng.uniform() * 2 - 1));
    Vec3 wi;
    reflect(wo, &wi);
    REQUIRE(wi == Vec3(-wo.x, -wo.y, wo.z));
  }
}

TEST_CASE("refract obeys Snell's law from both sides and fails exactly beyond the critical angle",
          "[part6][specular][refract]") {
  for (double ior : {1.45, 2.4}) {
    const double critical = std::asin(1.0 / ior) * 180.0 / M_PI;
    for (bool inside : {false, true})
      for (double deg = 0; deg < 90; deg += 0.5) {
        if (inside && std::fabs(deg - critical) < 0.01) continue;  // too close to call in float
        const Vec3 wo = at_angle(deg, inside);
        INFO("ior " << ior << (inside ? ", from inside" : ", from outside") << " at " << deg << " degrees");
        const Vec3 before(7, 7, 7);
        Vec3 wi = before;
        const bool ok = refract(wo, &wi, float(ior));
        if (inside && deg > critical) {
          CHECK_FALSE(ok);
          CHECK(wi == before);  // untouched
          continue;
        }
        REQUIRE(ok);
        CHECK(std::fabs(norm(wi) - 1.0f) < 1e-5f);
        CHECK(wi.z * wo.z < 0);  // the other side of the surface
        // In the plane of wo and the normal, on the other side of the normal.
        CHECK(std::fabs(wi.x * wo.y - wi.y * wo.x) < 1e-6f);
        CHECK(wi.x * wo.x + wi.y * wo.y <= 0);
        // n_o sin(theta_o) = n_i sin(theta_i).
        const double n_o = inside ? ior : 1.0, n_i = inside ? 1.0 : ior;
        CHECK(n_o * sin_theta(wo) == Approx(n_i * sin_theta(wi)).margin(2e-6));
        CHECK(std::fabs(wi.z) == Approx(refracted_cos(wo, ior)).margin(2e-6));
        // Reversible: light along the refracted path refracts back.
        Vec3 back;
        REQUIRE(refract(wi, &back, float(ior)));
        CHECK(norm(back - wo) < 2e-5f);
      }
  }
}

TEST_CASE("schlick_reflectance is R0 head-on, 1 at grazing, and grows in between", "[part6][specular][fresnel]") {
  for (float ior : {1.33f, 1.45f, 2.4f}) {
    const double r0 = std::pow((1.0 - ior) / (1.0 + ior), 2);
    CHECK(schlick_reflectance(1.0f, ior) == Approx(r0).epsilon(1e-5));
    CHECK(schlick_reflectance(0.0f, ior) == Approx(1.0).epsilon(1e-6));
    CHECK(schlick_reflectance(0.5f, ior) == Approx(r0 + (1 - r0) / 32.0).epsilon(1e-5));
    float last = 2;
    for (float c = 0; c <= 1.0f; c += 0.01f) {
      const float r = schlick_reflectance(c, ior);
      CHECK(r <= last);
      last = r;
    }
  }
}

TEST_CASE("mirror sample_f reflects with pdf 1 and weight = reflectance: a white mirror keeps all energy",
          "[part6][specular][mirror][furnace]") {
  Material m;
  m.type = MaterialType::Mirror;
  Rng rng(62);
  for (const Color& r : {Color(1.0f), Color(0.9f, 0.5f, 0.2f)}) {
    m.reflectance = r;
    for (int i = 0; i < 2000; ++i) {
      const Vec3 wo = at_angle(89.9 * rng.uniform(), false, 2 * M_PI * rng.uniform());
      Vec3 wi;
      float pdf = -1;
      const Color f = mirror_sample_f(m, wo, rng.uniform(), rng.uniform(), &wi, &pdf);
      REQUIRE(wi == Vec3(-wo.x, -wo.y, wo.z));
      REQUIRE(pdf == 1.0f);
      const Color weight = f * (std::fabs(wi.z) / pdf);
      for (int k = 0; k < 3; ++k) REQUIRE(weight[k] == Approx(r[k]).epsilon(1e-5));
    }
  }
  CHECK(kMirrorModel.delta);
  CHECK(kMirrorModel.f(m, Vec3(0, 0, 1), Vec3(0, 0, 1)) == Color(0.0f));
  CHECK(kMirrorModel.pdf(m, Vec3(0, 0, 1), Vec3(0, 0, 1)) == 0.0f);
}

TEST_CASE("glass sample_f reflects with Schlick's probability from both sides, at grazing angles too, chi-square",
          "[part6][specular][glass][chi2]") {
  struct Case {
    double ior, deg;
    bool inside;
  };
  const std::vector<Case> cases = {{1.45, 0, false},  {1.45, 45, false}, {1.45, 80, false}, {1.45, 89.5, false},
                                   {1.45, 0, true},   {1.45, 30, true},  {1.45, 43, true},  {1.45, 60, true},
                                   {2.4, 70, false},  {2.4, 24, true}};
  REQUIRE(int(cases.size()) == kChiSquareTests);
  uint64_t seed = 600;
  for (const Case& c : cases) {
    const Material m = glass(float(c.ior), Color(0.9f, 0.8f, 0.7f), Color(0.6f, 0.7f, 0.8f));
    const Vec3 wo = at_angle(c.deg, c.inside);
    const double R = expected_reflectance(wo, c.ior);
    const double ct = refracted_cos(wo, c.ior);
    const double eta = wo.z > 0 ? 1.0 / c.ior : c.ior;
    std::ostringstream what;
    what << "ior " << c.ior << (c.inside ? ", light leaving the glass" : ", light entering") << ", wo at " << c.deg
         << " degrees: R = " << R;
    INFO(what.str());
    std::vector<double> observed(2, 0.0);
    Rng rng(seed++);
    for (int i = 0; i < kSamples; ++i) {
      Vec3 wi;
      float pdf = -1;
      const Color f = glass_sample_f(m, wo, rng.uniform(), rng.uniform(), &wi, &pdf);
      REQUIRE(pdf > 0);
      const Color weight = f * (std::fabs(wi.z) / pdf);
      if (wi.z * wo.z > 0) {  // reflected
        observed[0] += 1;
        REQUIRE(norm(wi - Vec3(-wo.x, -wo.y, wo.z)) < 1e-6f);
        INFO("the reflection: pdf " << pdf << ", weight f |cos| / pdf " << weight.x << " " << weight.y << " "
             << weight.z << ". Hint: glass reports the probability of the branch it chose, as the course's "
                "does: pdf = R with f = R reflectance / |cos theta_i| for the reflection, pdf = 1 - R with f = "
                "(1 - R) transmittance eta^2 / |cos theta_i| for the refraction (the weight f |cos| / pdf is the "
                "same either way); R is Schlick's, with the cosine on the air side.");
        REQUIRE(pdf == Approx(R).epsilon(1e-4));
        for (int k = 0; k < 3; ++k) REQUIRE(weight[k] == Approx(m.reflectance[k]).epsilon(1e-4));
      } else {
        observed[1] += 1;
        REQUIRE(ct > 0);
        REQUIRE(std::fabs(wi.z) == Approx(ct).margin(2e-6));
        INFO("the refraction: pdf " << pdf << ", weight f |cos| / pdf " << weight.x << " " << weight.y << " "
             << weight.z << ". Hint: the refraction's pdf is 1 - R and f = (1 - R) transmittance eta^2 / "
                "|cos theta_i|, eta^2 the squared ratio of the indices (n on wo's side / n on wi's side).");
        REQUIRE(pdf == Approx(1 - R).epsilon(1e-4));
        for (int k = 0; k < 3; ++k) REQUIRE(weight[k] == Approx(m.transmittance[k] * eta * eta).epsilon(1e-4));
      }
    }
    const ChiSquareResult r = chi_square_test(observed, {kSamples * R, kSamples * (1 - R)}, true, 5.0);
    stats_log(what.str() + ": " + r.describe());
    INFO(r.describe() << "; level " << kAlphaEach);
    CHECK(r.p_value >= kAlphaEach);
  }
}

TEST_CASE("white glass keeps all energy: every sample's weight is 1, the refraction's eta^2 taken out",
          "[part6][specular][glass][furnace]") {
  const Material m = glass(1.5f);
  Rng rng(63);
  for (int i = 0; i < 20000; ++i) {
    const bool inside = rng.uniform() < 0.5f;
    const Vec3 wo = at_angle(89.9 * rng.uniform(), inside, 2 * M_PI * rng.uniform());
    Vec3 wi;
    float pdf = 0;
    const Color f = glass_sample_f(m, wo, rng.uniform(), rng.uniform(), &wi, &pdf);
    REQUIRE(pdf > 0);
    const double eta = wo.z > 0 ? 1.0 / 1.5 : 1.5;
    const double scaling = wi.z * wo.z < 0 ? eta * eta : 1.0;
    REQUIRE(f.x * std::fabs(wi.z) / pdf / scaling == Approx(1.0).epsilon(1e-4));
  }
}

TEST_CASE("glass chooses reflection with the same probability for a path and its reverse (Fresnel on the air side)",
          "[part6][specular][glass][reciprocity]") {
  // Light leaving the glass along wo came from inside along wi = refract(wo);
  // the reverse path enters along wi. Schlick's R must be the same for
  // both: the reported pdf of the reflection (u1 = 0 reflects).
  const Material m = glass(1.45f);
  for (double deg = 0; deg < 43.5; deg += 0.5) {
    const Vec3 wo = at_angle(deg, true);
    Vec3 t;
    REQUIRE(refract(wo, &t, m.ior));
    Vec3 wi;
    float R_inside = 0, R_outside = 0;
    glass_sample_f(m, wo, 0.0f, 0.5f, &wi, &R_inside);
    glass_sample_f(m, t, 0.0f, 0.5f, &wi, &R_outside);
    INFO("inside at " << deg << " degrees: reflection probability " << R_inside << " leaving the glass, "
                      << R_outside << " entering along the same path. Hint: Schlick's formula takes the cosine on "
                         "the air side: for light leaving the glass (wo.z < 0) that is the refracted direction's "
                         "|cos|, not |wo.z|.");
    CHECK(R_inside == Approx(R_outside).epsilon(1e-4));
  }
}

TEST_CASE("refraction sample_f: pdf 1, weight transmittance times eta^2, nothing at total internal reflection",
          "[part6][specular][refraction]") {
  Material m;
  m.type = MaterialType::Refraction;
  m.ior = 1.45f;
  m.transmittance = Color(0.9f, 0.7f, 0.5f);
  for (bool inside : {false, true})
    for (double deg = 0; deg < 90; deg += 1) {
      const Vec3 wo = at_angle(deg, inside);
      INFO((inside ? "inside" : "outside") << " at " << deg << " degrees");
      Vec3 wi;
      float pdf = -1;
      const Color f = refraction_sample_f(m, wo, 0.3f, 0.6f, &wi, &pdf);
      const double ct = refracted_cos(wo, 1.45);
      if (ct < 0) {
        CHECK(pdf == 0.0f);
        CHECK(f == Color(0.0f));
        continue;
      }
      REQUIRE(pdf == 1.0f);
      CHECK(wi.z * wo.z < 0);
      CHECK(std::fabs(wi.z) == Approx(ct).margin(2e-6));
      const double eta = inside ? 1.45 : 1.0 / 1.45;
      const Color weight = f * std::fabs(wi.z);
      for (int k = 0; k < 3; ++k) CHECK(weight[k] == Approx(m.transmittance[k] * eta * eta).epsilon(1e-4));
    }
  CHECK(kRefractionModel.delta);
  CHECK(kGlassModel.delta);
}
