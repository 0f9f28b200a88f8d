// Part 7: the microfacet BRDF (Beckmann's D, the conductor's Fresnel F,
// Smith's G) and its importance sampling, against formulas written here
// again in double precision.
//
// Statistics: one family at alpha = 0.01, Sidak-corrected over its K = 20
// tests (each at 1 - 0.99^(1/20) = 5.0e-4), fixed seeds:
//   12  chi-square tests of sample_f's directions against the density
//       D(h) cos theta_h / (4 |wi . h|) computed here, at alpha 0.005, 0.05,
//       0.25 and 0.5 and wo at 0, 45 and 75 degrees from the normal;
//       1,000,000 samples each, binned in 24 rings of equal solid angle by
//       24 sectors about the mirror direction within 6 alpha of it (the
//       whole sphere at alpha 0.5), plus one cell for directions outside
//       and samples below the surface (pdf 0); cells expecting fewer than 5
//       samples pooled;
//    6  z tests (white furnace): with F = 1, the mean of sample_f's weights
//       f cos / pdf over 200,000 samples against the quadrature of f cos
//       over the hemisphere, at alpha 0.05, 0.25 and 0.5 and wo at 0 and 60
//       degrees;
//    2  z tests: the cosine-sampled baseline (--bsdf-hemisphere) estimates
//       the same albedo, 400,000 samples each at alpha 0.25 and 0.5, wo at
//       30 degrees.
// The other checks are deterministic (stated tolerances).
//
// Deliberate bug (planted in a scratch copy) -> tests here that failed on it:
//   D without the 1 / cos^4                        -> D normalised, f formula, reported pdf
//   D with alpha instead of alpha^2                -> D normalised, f formula, reported pdf
//   F with k instead of k^2                        -> F values, f formula
//   pdf of the half vector, not converted to wi    -> reported pdf, furnace
//   theta_h = atan(sqrt(-alpha ln(1 - u1)))        -> chi-square, reported pdf, furnace
//   wi = wo reflected about the normal, not h      -> chi-square, reported pdf, furnace
//   Lambda with pi instead of sqrt(pi) (course's)  -> G is Smith's, f formula, furnace
//   tan^2 theta_h as (1 - cos^2) / cos^2 in float,  -> D formula (at alpha 0.005: 6982.14 for
//     or as tan(acos(h.z))^2                          6978.83), reported pdf; the failures say so
//   F at wi . h instead of wi.z                     -> f formula, reciprocity; the failure says so
// (Keeping samples below the surface changes nothing: their pdf, from
// microfacet_pdf, is 0 all the same.)
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "common/rng.h"
#include "pathtracer/radiance.h"
#include "stages/part7_microfacet/microfacet.h"
#include "tests/statistics/direction_bins.h"
#include "tests/statistics/hypothesis_tests.h"
#include "tests/statistics/special_functions.h"

using namespace pt;
using namespace pt::test;

namespace {

constexpr double kAlpha = 0.01;
constexpr int kTests = 20;
const double kAlphaEach = sidak(kAlpha, kTests);

Material conductor(float alpha, const Color& eta, const Color& k) {
  Material m;
  m.type = MaterialType::Microfacet;
  m.alpha = alpha;
  m.eta = eta;
  m.k = k;
  return m;
}
// F = 1 for every direction (eta = k = 0): a white conductor.
Material white(float alpha) { return conductor(alpha, Color(0.0f), Color(0.0f)); }
// Gold, as in the project's scenes (610, 550 and 470 nm).
Material gold(float alpha) { return conductor(alpha, Color(0.1884f, 0.3382f, 1.347f), Color(3.278f, 2.549f, 1.832f)); }

Vec3d dvec(const Vec3& v) { return Vec3d(v.x, v.y, v.z); }

Vec3 at_angle(double deg, double phi = 0.3) {
  const double t = deg * M_PI / 180.0;
  return Vec3(float(std::sin(t) * std::cos(phi)), float(std::sin(t) * std::sin(phi)), float(std::cos(t)));
}

// The formulas, again, in double.
// Beckmann's D at the unit half vector h (tan and cos from its components).
double beckmann(double alpha, const Vec3d& h) {
  if (!(h.z > 0)) return 0.0;
  const double c2 = h.z * h.z, t2 = (h.x * h.x + h.y * h.y) / c2;
  return std::exp(-t2 / (alpha * alpha)) / (M_PI * alpha * alpha * c2 * c2);
}
double smith_lambda(double alpha, double cos_t) {
  const double c = std::min(std::max(cos_t, -1.0 + 1e-5), 1.0 - 1e-5);
  const double a = c / (alpha * std::sqrt(1 - c * c));
  return 0.5 * (std::erf(a) - 1) + std::exp(-a * a) / (2 * a * std::sqrt(M_PI));
}
double smith_g(double alpha, const Vec3d& wo, const Vec3d& wi) {
  return 1.0 / (1.0 + smith_lambda(alpha, wo.z) + smith_lambda(alpha, wi.z));
}
double conductor_fresnel(double eta, double k, double c) {
  const double a = eta * eta + k * k, c2 = c * c;
  const double rs = (a - 2 * eta * c + c2) / (a + 2 * eta * c + c2);
  const double rp = (a * c2 - 2 * eta * c + 1) / (a * c2 + 2 * eta * c + 1);
  return 0.5 * (rs + rp);
}
// The density of sample_f's directions: D(h) cos theta_h / (4 |wi . h|)
// above the surface, 0 below.
double sampling_density(double alpha, const Vec3d& wo, const Vec3d& wi) {
  if (!(wo.z > 0) || !(wi.z > 0)) return 0.0;
  const Vec3d h = normalize(wo + wi);
  return beckmann(alpha, h) * h.z / (4 * std::fabs(dot(wi, h)));
}

// What a failure shows a student: where the value is off, by how much, and
// the likely cause in the assignment's words (Catch prints an INFO only
// when an assertion of its scope fails).
std::string rgb(const Color& c) {
  std::ostringstream s;
  s << "(" << c.x << ", " << c.y << ", " << c.z << ")";
  return s.str();
}
double relative_error(double got, double want) {
  return want != 0 ? std::fabs(got / want - 1) : std::fabs(got);
}

// D at the half vector h against the formula.
std::string d_hint(const Material& m, const Vec3& h, double got, double want) {
  std::ostringstream s;
  s << "alpha " << m.alpha << ", h = (" << h.x << ", " << h.y << ", " << h.z << "), theta_h "
    << std::acos(std::min(1.0, double(h.z))) * 180 / M_PI << " degrees: your D " << got << ", the formula " << want
    << " (off by " << relative_error(got, want) * 100 << " %). ";
  // tan^2 from the cosine alone, as a student may write it, in float.
  const float c = h.z, c2 = c * c, a2 = m.alpha * m.alpha;
  const float from_cos = std::exp(-((1.0f - c2) / c2) / a2) / (float(M_PI) * a2 * c2 * c2);
  if (relative_error(got, want) < 0.02 && std::fabs(got - from_cos) <= 1e-4 * std::fabs(from_cos))
    s << "Hint: your D is what tan^2 theta_h = (1 - cos^2 theta_h) / cos^2 theta_h gives in float. Near the "
         "normal cos theta_h is 0.9999..., so 1 - cos^2 keeps only a few digits, and exp(-tan^2 theta_h / "
         "alpha^2) magnifies the loss at small alpha. Take tan^2 theta_h from h's x and y: "
         "(h.x^2 + h.y^2) / h.z^2 (as the given microfacet_Lambda takes sin theta).";
  else if (relative_error(got, want) < 0.02)
    s << "Hint: this close, the formula is right and its float arithmetic is not: tan^2 theta_h from the cosine "
         "((1 - cos^2) / cos^2, or tan(acos(h.z))) loses its digits near the normal, which exp(-tan^2 theta_h / "
         "alpha^2) magnifies at small alpha. Take it from h's x and y: (h.x^2 + h.y^2) / h.z^2.";
  else
    s << "Hint: D = exp(-tan^2 theta_h / alpha^2) / (pi alpha^2 cos^4 theta_h): alpha squared in both places, "
         "the fourth power of cos theta_h = h.z, and 0 for h.z <= 0.";
  return s.str();
}

// microfacet_f(wo, wi) against the formula, factor by factor.
std::string f_hint(const Material& m, const Vec3& wo, const Vec3& wi, int k, double got, double want) {
  const Vec3d h = normalize(dvec(wo) + dvec(wi));
  const double F = conductor_fresnel(m.eta[k], m.k[k], wi.z), G = smith_g(m.alpha, dvec(wo), dvec(wi));
  const double D = beckmann(m.alpha, h), rest = G * D / (4 * double(wo.z) * wi.z);
  std::ostringstream s;
  s << "alpha " << m.alpha << ", channel " << k << ", cos theta_o " << wo.z << ", cos theta_i " << wi.z
    << ": your f " << got << ", expected " << want << " = F(wi) " << F << " * G " << G << " * D(h) " << D
    << " / (4 cos theta_o cos theta_i); your F(wi) " << microfacet_F(m, wi)[k] << ", G "
    << microfacet_G(m, wo, wi) << ", D(h) " << microfacet_D(m, Vec3(float(h.x), float(h.y), float(h.z))) << ". ";
  const double with_h = conductor_fresnel(m.eta[k], m.k[k], dot(dvec(wi), h)) * rest;
  if (relative_error(got, with_h) < 2e-3 && relative_error(got, want) >= 2e-3)
    s << "Hint: your f uses F at wi . h, the angle to the facet's normal. The course's F, and this part's "
         "contract, is F(wi): the angle to the surface's normal, cos theta = wi.z.";
  else
    s << "Hint: if one of your F, G, D differs from the expected one, its own test fails too: fix that first.";
  return s.str();
}

// An orthonormal frame about n, built independently of Frame::from_normal.
Frame frame_about(const Vec3& n_) {
  const Vec3d n = normalize(dvec(n_));
  const Vec3d seed = std::fabs(n.x) < 0.6 ? Vec3d(1, 0, 0) : Vec3d(0, 1, 0);
  const Vec3d x = normalize(seed - n * dot(seed, n)), y = cross(n, x);
  Frame f;
  f.x = Vec3(float(x.x), float(x.y), float(x.z));
  f.y = Vec3(float(y.x), float(y.y), float(y.z));
  f.z = Vec3(float(n.x), float(n.y), float(n.z));
  return f;
}

}  // namespace

TEST_CASE("Beckmann's D is the formula and is normalised: the integral of D(h) cos theta_h is 1", "[part7][microfacet]") {
  for (float alpha : {0.005f, 0.05f, 0.25f, 0.5f, 1.0f}) {
    const Material m = white(alpha);
    INFO("alpha " << alpha);
    // D depends on theta_h alone: 2 pi times the integral over theta_h of
    // D cos sin, by the midpoint rule on 2,000,000 steps.
    const int n = 2000000;
    double sum = 0;
    for (int i = 0; i < n; ++i) {
      const double t = (i + 0.5) / n * (M_PI / 2);
      sum += double(microfacet_D(m, Vec3(float(std::sin(t)), 0.0f, float(std::cos(t))))) * std::cos(t) * std::sin(t);
    }
    CHECK(2 * M_PI * sum * (M_PI / 2) / n == Approx(1.0).epsilon(2e-3));
    Rng rng(70);
    for (int i = 0; i < 1000; ++i) {
      const Vec3 h = at_angle(89.0 * rng.uniform(), 2 * M_PI * rng.uniform());
      const double want = beckmann(alpha, normalize(dvec(h)));
      const float got = microfacet_D(m, h);
      INFO(d_hint(m, h, got, want));
      REQUIRE(got == Approx(want).epsilon(1e-4).margin(1e-30));
    }
    CHECK(microfacet_D(m, Vec3(0.6f, 0.0f, -0.8f)) == 0.0f);
  }
}

TEST_CASE("microfacet_F is the conductor's Fresnel reflectance at wi's angle to the normal, per channel",
          "[part7][microfacet][fresnel]") {
  const Material m = gold(0.3f);
  for (int k = 0; k < 3; ++k) {
    const double eta = m.eta[k], kk = m.k[k];
    // Head-on: ((eta - 1)^2 + k^2) / ((eta + 1)^2 + k^2); grazing: 1.
    CHECK(microfacet_F(m, Vec3(0, 0, 1))[k] ==
          Approx(((eta - 1) * (eta - 1) + kk * kk) / ((eta + 1) * (eta + 1) + kk * kk)).epsilon(1e-5));
    CHECK(microfacet_F(m, Vec3(1, 0, 0))[k] == Approx(1.0).epsilon(1e-5));
  }
  for (double deg = 0; deg < 90; deg += 1) {
    const Color F = microfacet_F(m, at_angle(deg, 1.1));
    for (int k = 0; k < 3; ++k)
      CHECK(F[k] == Approx(conductor_fresnel(m.eta[k], m.k[k], std::cos(deg * M_PI / 180))).epsilon(1e-4));
  }
  CHECK(microfacet_F(white(0.3f), at_angle(40)) == Color(1.0f));
}

TEST_CASE("G is Smith's for Beckmann, 1 / (1 + Lambda(wi) + Lambda(wo)), never above 1", "[part7][microfacet]") {
  Rng rng(71);
  for (float alpha : {0.005f, 0.05f, 0.25f, 0.5f, 1.0f})
    for (int i = 0; i < 2000; ++i) {
      const Vec3 wo = at_angle(89.9 * rng.uniform(), 2 * M_PI * rng.uniform());
      const Vec3 wi = at_angle(89.9 * rng.uniform(), 2 * M_PI * rng.uniform());
      const double g = microfacet_G(white(alpha), wo, wi);
      INFO("alpha " << alpha << ", cos theta " << wo.z << " and " << wi.z);
      REQUIRE(g == Approx(smith_g(alpha, dvec(wo), dvec(wi))).epsilon(1e-4));
      REQUIRE(g <= 1.0 + 1e-6);
    }
}

TEST_CASE("microfacet_f is F(wi) G D(h) / (4 cos theta_o cos theta_i), and 0 unless both are above the surface",
          "[part7][microfacet]") {
  Rng rng(72);
  for (float alpha : {0.05f, 0.25f, 0.5f}) {
    const Material m = gold(alpha);
    for (int i = 0; i < 2000; ++i) {
      const Vec3 wo = at_angle(89 * rng.uniform(), 2 * M_PI * rng.uniform());
      const Vec3 wi = at_angle(89 * rng.uniform(), 2 * M_PI * rng.uniform());
      const Vec3d h = normalize(dvec(wo) + dvec(wi));
      const Color f = microfacet_f(m, wo, wi);
      for (int k = 0; k < 3; ++k) {
        const double want = conductor_fresnel(m.eta[k], m.k[k], wi.z) * smith_g(alpha, dvec(wo), dvec(wi)) *
                            beckmann(alpha, h) / (4 * double(wo.z) * wi.z);
        INFO(f_hint(m, wo, wi, k, f[k], want));
        REQUIRE(f[k] == Approx(want).epsilon(2e-3).margin(1e-30));
      }
    }
    const Vec3 below(0.3f, 0.0f, -0.95394f);
    CHECK(microfacet_f(m, at_angle(30), below) == Color(0.0f));
    CHECK(microfacet_f(m, below, at_angle(30)) == Color(0.0f));
  }
}

TEST_CASE("microfacet sample_f fits D(h) cos theta_h / (4 |wi . h|), chi-square, alpha 0.005 to 0.5, grazing wo",
          "[part7][microfacet][sampling][chi2]") {
  const int samples = 1000000;
  uint64_t seed = 700;
  for (float alpha : {0.005f, 0.05f, 0.25f, 0.5f})
    for (double deg : {0.0, 45.0, 75.0}) {
      const Material m = white(alpha);
      const Vec3 wo = at_angle(deg);
      DirectionBins bins;
      bins.frame = frame_about(Vec3(-wo.x, -wo.y, wo.z));  // about the mirror direction
      bins.n_cos = 24;
      bins.n_phi = 24;
      bins.cos_min = 6 * alpha < M_PI ? std::cos(6.0 * alpha) : -1.0;
      std::vector<double> observed(size_t(bins.size()), 0.0);
      Rng rng(seed++);
      for (int i = 0; i < samples; ++i) {
        Vec3 wi;
        float pdf = 0;
        microfacet_sample_f(m, wo, rng.uniform(), rng.uniform(), &wi, &pdf);
        observed[size_t(pdf > 0 ? bins.cell(wi) : bins.outside())] += 1;
      }
      std::vector<double> expected =
          bins.integrate([&](const Vec3& w) { return sampling_density(alpha, dvec(wo), dvec(w)); },
                         alpha < 0.1f ? 96 : 16, false, 4);
      double inside = 0;
      for (double& e : expected) inside += e;
      expected[size_t(bins.outside())] = std::max(0.0, 1.0 - inside);
      for (double& e : expected) e *= samples;
      const ChiSquareResult r = chi_square_test(observed, expected, false);
      std::ostringstream what;
      what << "alpha " << alpha << ", wo at " << deg << " degrees: " << r.describe() << "; level " << kAlphaEach;
      stats_log(what.str());
      INFO(what.str());
      CHECK(r.p_value >= kAlphaEach);
    }
}

TEST_CASE("microfacet sample_f reports the pdf of wi (not of h) and f, and no sample below the surface",
          "[part7][microfacet][sampling][pdf]") {
  Rng rng(73);
  for (float alpha : {0.005f, 0.05f, 0.25f, 0.5f}) {
    const Material m = gold(alpha);
    int below = 0;
    for (int i = 0; i < 20000; ++i) {
      const Vec3 wo = at_angle(85 * rng.uniform(), 2 * M_PI * rng.uniform());
      Vec3 wi;
      float pdf = -1;
      const Color f = microfacet_sample_f(m, wo, rng.uniform(), rng.uniform(), &wi, &pdf);
      REQUIRE(std::fabs(norm(wi) - 1.0f) < 1e-4f);
      if (!(wi.z > 0)) {
        ++below;
        REQUIRE(pdf == 0.0f);
        continue;
      }
      INFO("alpha " << alpha << ", wo.z " << wo.z << ", wi.z " << wi.z);
      const double want = sampling_density(alpha, dvec(wo), dvec(wi));
      const double wi_dot_h = std::fabs(dot(dvec(wi), normalize(dvec(wo) + dvec(wi))));
      {
        INFO((relative_error(pdf, want * 4 * wi_dot_h) < 2e-3
                  ? "Hint: your pdf is the half vector's density, D(h) cos theta_h: divide it by 4 |wi . h| (the "
                    "Jacobian of reflecting about h) to get wi's."
                  : relative_error(pdf, want) < 0.02
                        ? "Hint: this close, the formula is right and its float arithmetic is not. The pdf is D(h) "
                          "cos theta_h / (4 |wi . h|) with your microfacet_D: if the test of Beckmann's D fails, "
                          "fix D first."
                        : "Hint: the pdf of wi is D(h) cos theta_h / (4 |wi . h|), with h = normalize(wo + wi)."));
        REQUIRE(pdf == Approx(want).epsilon(2e-3));
      }
      REQUIRE(microfacet_pdf(m, wo, wi) == Approx(pdf).epsilon(1e-5));
      const Color g = microfacet_f(m, wo, wi);
      INFO("Hint: the f that sample_f returns is microfacet_f(m, wo, wi) for the wi it drew (call it, as the given "
           "microfacet_sample_f_cosine does).");
      for (int k = 0; k < 3; ++k) REQUIRE(f[k] == Approx(g[k]).epsilon(1e-5));
    }
    if (alpha >= 0.25f) CHECK(below > 0);  // rough lobes reach below the horizon at grazing wo
  }
  // Head-on, the density's integral over the hemisphere is the probability
  // that the facet normal is within 45 degrees of the normal: 1 - e^(-1/alpha^2).
  for (float alpha : {0.25f, 0.5f, 1.0f}) {
    const Material m = white(alpha);
    const double total = integrate_sphere([&](const Vec3& w) { return double(microfacet_pdf(m, Vec3(0, 0, 1), w)); }, 600);
    INFO("alpha " << alpha);
    CHECK(total == Approx(1.0 - std::exp(-1.0 / (alpha * alpha))).epsilon(2e-3));
  }
}

TEST_CASE("white furnace: with F = 1 sample_f's weights average the albedo, 85% to 100% at alpha <= 0.5",
          "[part7][microfacet][furnace]") {
  uint64_t seed = 750;
  for (float alpha : {0.05f, 0.25f, 0.5f})
    for (double deg : {0.0, 60.0}) {
      const Material m = white(alpha);
      const Vec3 wo = at_angle(deg);
      // The albedo, integral of f cos over wi, written over the half vector
      // (d omega_i = 4 |wi . h| d omega_h) with t = tan^2 theta_h / alpha^2
      // = -ln(1 - u): f cos / pdf = G |wo . h| / (cos theta_o cos theta_h).
      const int nu = 800, nphi = 800;
      double albedo = 0;
      for (int i = 0; i < nu; ++i) {
        const double t = -std::log(1 - (i + 0.5) / nu), th = std::atan(alpha * std::sqrt(t));
        for (int j = 0; j < nphi; ++j) {
          const double ph = (j + 0.5) / nphi * 2 * M_PI;
          const Vec3d h(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
          const Vec3d o = dvec(wo), wi = h * (2 * dot(o, h)) - o;
          if (wi.z > 0) albedo += smith_g(alpha, o, wi) * dot(o, h) / (o.z * h.z);
        }
      }
      albedo /= double(nu) * nphi;
      RunningStats s;
      Rng rng(seed++);
      for (int i = 0; i < 200000; ++i) {
        Vec3 wi;
        float pdf = 0;
        const Color f = microfacet_sample_f(m, wo, rng.uniform(), rng.uniform(), &wi, &pdf);
        s.add(pdf > 0 ? double(f.y) * wi.z / pdf : 0.0);
      }
      // The quadrature is good to 1e-4 (800 x 800 points; 400 x 800 give
      // the same to 1e-4), which the z test adds to the mean's error: at
      // small alpha the weights barely vary.
      const double se = std::sqrt(s.variance() / double(s.n) + 1e-8);
      const double z = (s.mean - albedo) / se, p = 2 * normal_sf(std::fabs(z));
      std::ostringstream what;
      what << "alpha " << alpha << ", wo at " << deg << " degrees: albedo " << albedo << ", sample_f's weights "
           << s.mean << " +- " << s.std_error() << ", z = " << z << ", p = " << p;
      stats_log(what.str());
      INFO(what.str());
      CHECK(albedo >= 0.85);
      CHECK(albedo <= 1.0 + 1e-4);
      CHECK(p >= kAlphaEach);
    }
}

// The write-up's baseline (--bsdf-hemisphere): microfacet_f with
// cosine-weighted directions, the course's starter sample_f. Given code,
// checked here so that the comparison it makes is fair: the same BRDF, an
// unbiased estimate of the same albedo.
TEST_CASE("the cosine-sampled microfacet model draws cosine-weighted directions and estimates the same albedo",
          "[part7][microfacet][furnace]") {
  CHECK(kMicrofacetCosineModel.f == kMicrofacetModel.f);
  CHECK(kMicrofacetCosineModel.pdf == microfacet_pdf_cosine);
  CHECK(!kMicrofacetCosineModel.delta);
  const Material g = gold(0.25f);
  const Vec3 wo = at_angle(30.0);
  Rng check_rng(760);
  for (int i = 0; i < 1000; ++i) {
    const float u1 = check_rng.uniform(), u2 = check_rng.uniform();
    Vec3 wi;
    float pdf = 0;
    const Color f = microfacet_sample_f_cosine(g, wo, u1, u2, &wi, &pdf);
    REQUIRE(wi == sample_cosine_hemisphere(u1, u2));
    REQUIRE(pdf == cosine_hemisphere_pdf(wi));
    REQUIRE(pdf == microfacet_pdf_cosine(g, wo, wi));
    REQUIRE(f == microfacet_f(g, wo, wi));
  }
  uint64_t seed = 770;
  for (float alpha : {0.25f, 0.5f}) {
    const Material m = white(alpha);
    RunningStats cosine, importance;
    Rng rng(seed++);
    for (int i = 0; i < 400000; ++i) {
      Vec3 wi;
      float pdf = 0;
      Color f = microfacet_sample_f_cosine(m, wo, rng.uniform(), rng.uniform(), &wi, &pdf);
      cosine.add(pdf > 0 ? double(f.y) * wi.z / pdf : 0.0);
      f = microfacet_sample_f(m, wo, rng.uniform(), rng.uniform(), &wi, &pdf);
      importance.add(pdf > 0 ? double(f.y) * wi.z / pdf : 0.0);
    }
    // Two independent estimates of one albedo.
    const double se = std::sqrt(cosine.variance() / double(cosine.n) + importance.variance() / double(importance.n));
    const double z = (cosine.mean - importance.mean) / se, p = 2 * normal_sf(std::fabs(z));
    std::ostringstream what;
    what << "alpha " << alpha << ": cosine-sampled " << cosine.mean << " +- " << cosine.std_error()
         << ", importance-sampled " << importance.mean << " +- " << importance.std_error() << ", z = " << z
         << ", p = " << p;
    stats_log(what.str());
    INFO(what.str());
    CHECK(p >= kAlphaEach);
    // Importance sampling is the better estimator of the two.
    CHECK(importance.variance() < cosine.variance());
  }
}

TEST_CASE("the bsdf-hemisphere flag gives microfacet materials the cosine-sampled model from part 7 on, nothing else",
          "[part7][microfacet]") {
  Scene s;
  for (MaterialType t : {MaterialType::Diffuse, MaterialType::Microfacet, MaterialType::Mirror, MaterialType::Glass}) {
    Material m = gold(0.25f);
    m.type = t;
    s.materials.push_back(m);
  }
  for (int part : {5, 6, 7, 8, 9})
    for (bool hemisphere : {false, true}) {
      INFO("part " << part << (hemisphere ? ", --bsdf-hemisphere" : ""));
      const auto shading = part_shading(s, part, hemisphere);
      REQUIRE(shading->materials.size() == 4u);
      const BSDFModel* want = part < 7 ? nullptr : hemisphere ? &kMicrofacetCosineModel : &kMicrofacetModel;
      CHECK(shading->materials[1].model == want);
      CHECK(shading->materials[0].model == nullptr);  // diffuse: the given model
      CHECK(shading->materials[2].model == part_shading(s, part)->materials[2].model);
      CHECK(shading->materials[3].model == part_shading(s, part)->materials[3].model);
    }
}

TEST_CASE("reciprocity: f(wo, wi) = f(wi, wo) with a constant F, the course's F(wi) makes it F(wi) / F(wo)",
          "[part7][microfacet][reciprocity]") {
  Rng rng(74);
  for (float alpha : {0.05f, 0.25f, 0.5f}) {
    for (int i = 0; i < 2000; ++i) {
      const Vec3 a = at_angle(85 * rng.uniform(), 2 * M_PI * rng.uniform());
      const Vec3 b = at_angle(85 * rng.uniform(), 2 * M_PI * rng.uniform());
      const Material w = white(alpha);
      REQUIRE(microfacet_f(w, a, b).y == Approx(microfacet_f(w, b, a).y).epsilon(1e-4).margin(1e-30));
      const Material g = gold(alpha);
      const Color ab = microfacet_f(g, a, b), ba = microfacet_f(g, b, a);
      const Color Fb = microfacet_F(g, b), Fa = microfacet_F(g, a);
      INFO("alpha " << alpha << ", cos theta " << a.z << " and " << b.z << ": f(a, b) " << rgb(ab) << ", f(b, a) " << rgb(ba)
           << ", F(a) " << rgb(Fa) << ", F(b) " << rgb(Fb)
           << ". Hint: with the course's F(wi), f(wo, wi) F(wo) = f(wi, wo) F(wi) exactly as G and D(h) are the same "
              "both ways; a mismatch means F is taken at another angle than wi.z (wi . h, say), or D or G treat wo "
              "and wi differently.");
      for (int k = 0; k < 3; ++k) REQUIRE(ab[k] * Fa[k] == Approx(ba[k] * Fb[k]).epsilon(1e-4).margin(1e-30));
    }
  }
}
