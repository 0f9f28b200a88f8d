// The function checks of parts 3, 6, 7, 8 and 9 (probe.h).
//
// Every check calls a student function on fixed inputs and reports what it
// returned, or bookkeeping over what it returned (averages, counts,
// fractions, agreement between two of its outputs). Nothing here computes
// what the answer should be: the reference build's own figures are the
// expected ones.
//
// Sampling functions are run over a stratified grid of (u1, u2) (the
// midpoints (i + 0.5) / N). That set of points is unchanged by u -> 1 - u
// and by swapping u1 and u2, so a sampler that differs from the reference
// only so (a microfacet sampler drawing the azimuth from u1, or using
// ln u instead of ln(1 - u)) reports the same averages up to round-off.
// Any other correct mapping differs by the grid's quadrature error, which
// the tolerances below leave room for (each check says how much).
#include <cmath>
#include <vector>

#include "common/bsdf.h"
#include "common/camera.h"
#include "common/environment.h"
#include "common/math_constants.h"
#include "common/ray.h"
#include "pathtracer/probe.h"
#include "stages/part6_mirror_glass/specular.h"
#include "stages/part7_microfacet/microfacet.h"
#include "stages/part8_environment_light/environment_sampling.h"
#include "stages/part9_depth_of_field/thin_lens.h"

namespace pt::probe {

namespace {

const double kNaN = std::nan("");

void put(std::vector<double>* v, const Vec3& a) {
  v->push_back(a.x);
  v->push_back(a.y);
  v->push_back(a.z);
}
void put(std::vector<double>* v, const Vec3d& a) {
  v->push_back(a.x);
  v->push_back(a.y);
  v->push_back(a.z);
}
void put_nan(std::vector<double>* v, int n) {
  for (int i = 0; i < n; ++i) v->push_back(kNaN);
}

// A unit local direction from the cosine of its polar angle and its azimuth.
Vec3 local_dir(float cos_theta, float phi) {
  const float s = std::sqrt(std::fmax(0.0f, 1.0f - cos_theta * cos_theta));
  return Vec3(s * std::cos(phi), s * std::sin(phi), cos_theta);
}

// Directions above the surface, head-on to grazing, at a few azimuths.
std::vector<Vec3> upper_dirs() {
  std::vector<Vec3> d;
  const float cosines[] = {1.0f, 0.95f, 0.8f, 0.6f, 0.35f, 0.15f, 0.02f};
  const float phis[] = {0.0f, 1.1f, 2.7f, 4.4f};
  for (float c : cosines)
    for (float p : phis) {
      if (c == 1.0f && p != 0.0f) continue;
      d.push_back(local_dir(c, p));
    }
  return d;
}

// The same and their mirror images below the surface.
std::vector<Vec3> both_sides_dirs() {
  std::vector<Vec3> d = upper_dirs();
  const size_t n = d.size();
  for (size_t i = 0; i < n; ++i) d.push_back(Vec3(d[i].x, d[i].y, -d[i].z));
  return d;
}

// ---------------------------------------------------------------- part 3

std::vector<Check> probe_diffuse_f() {
  std::vector<Check> out;
  const Color albedos[] = {Color(0.5f), Color(0.8f, 0.2f, 0.1f), Color(1.0f), Color(0.05f, 0.6f, 0.93f)};
  const std::vector<Vec3> dirs = upper_dirs();
  std::vector<double> v;
  for (const Color& a : albedos) {
    Material m;
    m.albedo = a;
    for (size_t i = 0; i < dirs.size(); i += 3)
      for (size_t j = 1; j < dirs.size(); j += 4) put(&v, diffuse_f(m, dirs[i], dirs[j]));
  }
  add(&out, "diffuse_f: f of 4 albedos for pairs of directions above the surface", v);
  return out;
}

// ---------------------------------------------------------------- part 6

const float kIors[] = {1.2f, 1.45f, 1.9f, 2.4f};

std::vector<Check> probe_reflect() {
  std::vector<Check> out;
  std::vector<double> v;
  for (const Vec3& wo : both_sides_dirs()) {
    Vec3 wi(5.0f, -6.0f, 7.0f);
    reflect(wo, &wi);
    put(&v, wi);
  }
  add(&out, "reflect: wi of directions above and below the surface", v);
  return out;
}

std::vector<Check> probe_refract() {
  std::vector<Check> out;
  for (float ior : kIors) {
    std::vector<double> ok, dirs;
    for (const Vec3& wo : both_sides_dirs()) {
      Vec3 wi(5.0f, -6.0f, 7.0f);  // must stay so at total internal reflection
      const bool r = refract(wo, &wi, ior);
      ok.push_back(r ? 1.0 : 0.0);
      put(&dirs, wi);
    }
    add(&out, "refract: returned true (1) or false (0), ior " + std::to_string(ior), ok, 0.0, 0.0);
    add(&out, "refract: wi (left unchanged at total internal reflection), ior " + std::to_string(ior), dirs);
  }
  return out;
}

std::vector<Check> probe_schlick() {
  std::vector<Check> out;
  const float cosines[] = {0.0f, 0.01f, 0.1f, 0.25f, 0.4f, 0.5f, 0.6f, 0.75f, 0.9f, 0.99f, 1.0f};
  std::vector<double> v;
  for (float ior : kIors)
    for (float c : cosines) v.push_back(schlick_reflectance(c, ior));
  add(&out, "schlick_reflectance: R for cos theta 0..1 and ior 1.2, 1.45, 1.9, 2.4", v);
  return out;
}

std::vector<Material> specular_materials() {
  std::vector<Material> ms;
  const Color refl[] = {Color(1.0f), Color(0.9f, 0.8f, 0.7f), Color(0.3f, 0.6f, 0.95f)};
  const Color trans[] = {Color(1.0f), Color(0.6f, 0.9f, 1.0f), Color(0.85f, 0.5f, 0.2f)};
  const float iors[] = {1.45f, 1.33f, 2.4f};
  for (int i = 0; i < 3; ++i) {
    Material m;
    m.reflectance = refl[i];
    m.transmittance = trans[i];
    m.ior = iors[i];
    ms.push_back(m);
  }
  return ms;
}

std::vector<Check> probe_mirror_sample_f() {
  std::vector<Check> out;
  std::vector<double> v;
  for (const Material& m : specular_materials())
    for (const Vec3& wo : both_sides_dirs()) {
      Vec3 wi(5.0f, -6.0f, 7.0f);
      float pdf = -1.0f;
      const Color f = mirror_sample_f(m, wo, 0.3f, 0.6f, &wi, &pdf);
      put(&v, wi);
      v.push_back(pdf);
      put(&v, f);
    }
  add(&out, "mirror_sample_f: wi, pdf, f for 3 reflectances, directions above and below", v);
  return out;
}

std::vector<Check> probe_refraction_sample_f() {
  std::vector<Check> out;
  const float us[][2] = {{0.3f, 0.6f}, {0.02f, 0.97f}, {0.85f, 0.15f}};
  for (const auto& u : us) {
    std::vector<double> pdfs, rest;
    for (const Material& m : specular_materials())
      for (const Vec3& wo : both_sides_dirs()) {
        Vec3 wi(5.0f, -6.0f, 7.0f);
        float pdf = -1.0f;
        const Color f = refraction_sample_f(m, wo, u[0], u[1], &wi, &pdf);
        pdfs.push_back(pdf);
        if (pdf > 0) {  // a direction sent: where and with what f
          put(&rest, wi);
          put(&rest, f);
        } else {
          put_nan(&rest, 6);
        }
      }
    const std::string at = " (u1, u2 = " + std::to_string(u[0]) + ", " + std::to_string(u[1]) + ")";
    add(&out, "refraction_sample_f: pdf (0 at total internal reflection)" + at, pdfs);
    add(&out, "refraction_sample_f: wi and f where pdf > 0" + at, rest);
  }
  return out;
}

// Glass over 1024 points (u1, u2) of a lattice (u1 = (k + 0.5) / 1024, u2
// the same of 397 k mod 1024: each number takes all 1024 values once).
// Which lobe each sample takes is the sampler's convention, so per lobe
// only what any correct sampler shares: how often it is taken (about R:
// the lattice resolves it to 1/1024 whichever number decides, tolerance
// 3e-3) and, for the samples that take it, the
// direction, pdf and weight f |cos| / pdf, each the same for every sample
// of the lobe (exact).
std::vector<Check> probe_glass_sample_f() {
  std::vector<Check> out;
  constexpr int N = 1024;
  std::vector<Vec3> wos;
  const float outside[] = {1.0f, 0.9f, 0.7f, 0.45f, 0.2f, 0.05f};
  const float inside[] = {-1.0f, -0.95f, -0.85f, -0.75f, -0.6f, -0.3f, -0.05f};  // some past the critical angle
  for (float c : outside) wos.push_back(local_dir(c, 0.7f));
  for (float c : inside) wos.push_back(local_dir(c, 2.3f));
  for (const Material& m : specular_materials()) {
    std::vector<double> fractions, lobes;
    for (const Vec3& wo : wos) {
      int n_refl = 0, n_refr = 0, n_none = 0;
      Vec3d sum_wi[2];
      double sum_pdf[2] = {0, 0};
      Vec3d sum_w[2];
      for (int k = 0; k < N; ++k) {
        Vec3 wi(5.0f, -6.0f, 7.0f);
        float pdf = -1.0f;
        const Color f = glass_sample_f(m, wo, (k + 0.5f) / N, ((k * 397) % N + 0.5f) / N, &wi, &pdf);
        if (!(pdf > 0) || !std::isfinite(pdf)) {
          ++n_none;
          continue;
        }
        const int lobe = (wi.z > 0) == (wo.z > 0) ? 0 : 1;  // 0 reflection, 1 refraction
        (lobe == 0 ? n_refl : n_refr)++;
        sum_wi[lobe] += Vec3d(wi);
        sum_pdf[lobe] += pdf;
        sum_w[lobe] += Vec3d(f) * (double(std::fabs(wi.z)) / double(pdf));
      }
      fractions.push_back(double(n_refl) / N);
      fractions.push_back(double(n_refr) / N);
      fractions.push_back(double(n_none) / N);
      for (int lobe = 0; lobe < 2; ++lobe) {
        const int n = lobe == 0 ? n_refl : n_refr;
        if (n == 0) {
          put_nan(&lobes, 7);
          continue;
        }
        put(&lobes, sum_wi[lobe] / double(n));
        lobes.push_back(sum_pdf[lobe] / n);
        put(&lobes, sum_w[lobe] / double(n));
      }
    }
    const std::string mat = " (ior " + std::to_string(m.ior) + ")";
    add(&out, "glass_sample_f: fraction of (u1, u2) reflecting, refracting, sending nothing" + mat, fractions, 3e-3,
        0.0);
    add(&out,
        "glass_sample_f: per lobe (reflection, refraction) its mean wi, mean pdf and mean weight f |cos| / pdf" + mat,
        lobes, 2e-5, 2e-4);
  }
  return out;
}

// ---------------------------------------------------------------- part 7

std::vector<Material> microfacet_materials() {
  std::vector<Material> ms;
  const float alphas[] = {0.005f, 0.05f, 0.25f, 0.5f};
  const Color etas[] = {Color(0.143f, 0.374f, 1.442f), Color(0.2f, 0.924f, 1.102f), Color(1.5f, 1.2f, 2.0f),
                        Color(0.059f, 0.0595f, 0.0568f)};
  const Color ks[] = {Color(3.983f, 2.386f, 1.603f), Color(3.912f, 2.452f, 2.142f), Color(0.0f, 0.5f, 0.9f),
                      Color(4.28f, 3.52f, 2.75f)};
  for (int i = 0; i < 4; ++i) {
    Material m;
    m.alpha = alphas[i];
    m.eta = etas[i];
    m.k = ks[i];
    ms.push_back(m);
  }
  return ms;
}

// Float formulas of Beckmann's D differ by how tan theta_h is computed,
// which near the normal of a near-mirror (alpha 0.005, tan theta_h ~
// 0.005) loses digits to cancellation: that material gets a loose
// relative tolerance.
double mf_rel(const Material& m) { return m.alpha < 0.01f ? 2e-2 : (m.alpha < 0.1f ? 1e-3 : 3e-4); }

// Half vectors near the normal, at the lobe's width and beyond.
std::vector<Vec3> half_vectors(const Material& m) {
  std::vector<Vec3> hs;
  const float spreads[] = {0.0f, 0.4f, 1.0f, 2.0f, 3.5f};
  const float phis[] = {0.3f, 2.0f, 4.1f};
  for (float s : spreads)
    for (float p : phis) {
      const float theta = std::atan(s * m.alpha);
      hs.push_back(local_dir(std::cos(theta), p));
    }
  // And far from the normal: 30, 60, 80 degrees.
  for (float deg : {30.0f, 60.0f, 80.0f}) hs.push_back(local_dir(std::cos(deg * kPi / 180.0f), 1.0f));
  return hs;
}

// (wo, wi) pairs: wi near wo's mirror direction (the lobe) and anywhere.
std::vector<std::pair<Vec3, Vec3>> mf_pairs(const Material& m) {
  std::vector<std::pair<Vec3, Vec3>> ps;
  const float wo_cos[] = {0.97f, 0.7f, 0.3f, 0.08f};
  for (float c : wo_cos) {
    const Vec3 wo = local_dir(c, 0.6f);
    for (const Vec3& h : half_vectors(m)) {
      const Vec3 wi = h * (2.0f * dot(wo, h)) - wo;  // input construction: a wi whose half vector is near h
      ps.push_back({wo, normalize(wi)});
    }
  }
  const std::vector<Vec3> dirs = both_sides_dirs();
  for (size_t i = 0; i < dirs.size(); i += 5)
    for (size_t j = 2; j < dirs.size(); j += 7) ps.push_back({dirs[i], dirs[j]});
  return ps;
}

std::vector<Check> probe_microfacet_D() {
  std::vector<Check> out;
  for (const Material& m : microfacet_materials()) {
    std::vector<double> v;
    for (const Vec3& h : half_vectors(m)) v.push_back(microfacet_D(m, h));
    v.push_back(microfacet_D(m, Vec3(0.0f, 0.6f, -0.8f)));  // below the surface
    add(&out, "microfacet_D: D of half vectors, alpha " + std::to_string(m.alpha), v, 1e-5, mf_rel(m));
  }
  return out;
}

std::vector<Check> probe_microfacet_F() {
  std::vector<Check> out;
  std::vector<double> v;
  for (const Material& m : microfacet_materials())
    for (const Vec3& wi : upper_dirs()) put(&v, microfacet_F(m, wi));
  add(&out, "microfacet_F: F of 4 metals for directions above the surface", v);
  return out;
}

std::vector<Check> probe_microfacet_f() {
  std::vector<Check> out;
  for (const Material& m : microfacet_materials()) {
    std::vector<double> v;
    for (const auto& p : mf_pairs(m)) put(&v, microfacet_f(m, p.first, p.second));
    add(&out, "microfacet_f: f for (wo, wi) pairs in and out of the lobe, alpha " + std::to_string(m.alpha), v, 1e-5,
        mf_rel(m));
  }
  return out;
}

std::vector<Check> probe_microfacet_pdf() {
  std::vector<Check> out;
  for (const Material& m : microfacet_materials()) {
    std::vector<double> v;
    for (const auto& p : mf_pairs(m)) v.push_back(microfacet_pdf(m, p.first, p.second));
    add(&out, "microfacet_pdf: pdf for (wo, wi) pairs in and out of the lobe, alpha " + std::to_string(m.alpha), v,
        1e-5, mf_rel(m));
  }
  return out;
}

// Over a 64 x 64 grid of (u1, u2) per material and wo: the fraction of
// samples sending nothing (pdf 0, wi below), the mean weight f cos / pdf
// (the albedo's estimate), the mean wi of the samples sent, and the
// fraction whose pdf or f disagrees (by over 5 %) with microfacet_pdf /
// microfacet_f at the same (wo, wi). Tolerances: abs 5e-3 on fractions and
// means, rel 5e-3 on the weight: a different but correct mapping of the
// grid measured differences below 1e-3 (the sampled lobe is smooth in u;
// only the horizon's cut and the grid's 1/64 steps move).
std::vector<Check> probe_microfacet_sample_f() {
  std::vector<Check> out;
  constexpr int N = 64;
  for (const Material& m : microfacet_materials()) {
    std::vector<double> sent, weight, mean_dir, consistency;
    for (float c : {0.95f, 0.6f, 0.25f, -0.5f}) {
      const Vec3 wo = local_dir(c, 0.9f);
      int n_none = 0, n_pdf_off = 0, n_f_off = 0;
      Vec3d sum_w, sum_wi;
      for (int i = 0; i < N; ++i)
        for (int j = 0; j < N; ++j) {
          Vec3 wi(5.0f, -6.0f, 7.0f);
          float pdf = -1.0f;
          const Color f = microfacet_sample_f(m, wo, (i + 0.5f) / N, (j + 0.5f) / N, &wi, &pdf);
          if (!(pdf > 0) || !std::isfinite(pdf) || !(wi.z > 0)) {
            ++n_none;
            continue;
          }
          sum_w += Vec3d(f) * (double(wi.z) / double(pdf));
          sum_wi += Vec3d(wi);
          const double p2 = microfacet_pdf(m, wo, wi);
          if (!(std::fabs(p2 - pdf) <= 0.05 * std::fabs(p2) + 1e-6)) ++n_pdf_off;
          const Color f2 = microfacet_f(m, wo, wi);
          for (int k = 0; k < 3; ++k)
            if (!(std::fabs(f2[k] - f[k]) <= 0.05f * std::fabs(f2[k]) + 1e-6f)) {
              ++n_f_off;
              break;
            }
        }
      const int n_sent = N * N - n_none;
      sent.push_back(double(n_none) / (N * N));
      put(&weight, sum_w / double(N * N));
      if (n_sent > 0) put(&mean_dir, sum_wi / double(n_sent));
      else put_nan(&mean_dir, 3);
      consistency.push_back(double(n_pdf_off) / (N * N));
      consistency.push_back(double(n_f_off) / (N * N));
    }
    const std::string a = ", alpha " + std::to_string(m.alpha) + " (wo cos 0.95, 0.6, 0.25, -0.5)";
    add(&out, "microfacet_sample_f: fraction of samples sending nothing" + a, sent, 5e-3, 0.0);
    add(&out, "microfacet_sample_f: mean weight f cos / pdf over the grid" + a, weight, 2e-3, 5e-3);
    add(&out, "microfacet_sample_f: mean sampled wi" + a, mean_dir, 5e-3, 0.0);
    add(&out, "microfacet_sample_f: fraction whose pdf, f differ from microfacet_pdf, microfacet_f" + a, consistency,
        5e-3, 0.0);
  }
  return out;
}

// ---------------------------------------------------------------- part 8

// A synthetic map, not symmetric: a colour gradient, a bright spot and a
// black patch (every row still sends light).
EnvironmentMap synthetic_map(int w, int h) {
  EnvironmentMap map;
  map.width = w;
  map.height = h;
  map.texels.resize(size_t(w) * size_t(h));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      Color c(0.2f + 0.03f * x + 0.05f * y, 0.1f + 0.02f * float(w - 1 - x), 0.05f + 0.4f * float(y) / float(h));
      if (x == (5 * w) / 8 && y == h / 3) c = Color(60.0f, 45.0f, 30.0f);
      if (x == (5 * w) / 8 + 1 && y == h / 3) c = Color(20.0f, 18.0f, 12.0f);
      if (x >= w / 8 && x < w / 8 + 3 && y == (2 * h) / 3) c = Color(0.0f);
      map.texels[size_t(y) * size_t(w) + size_t(x)] = c;
    }
  return map;
}

// Arbitrary texel weights (some zero, one bright).
double given_weight(int x, int y) { return (1.3 + (y * 7) % 5) * double((x * 3 + y) % 7) * (x == 19 && y == 5 ? 9.0 : 1.0); }

// A map whose light follows those weights times a smooth colour, so that
// radiance / pdf varies little over the sphere and the grid's estimate of
// its integral has a small quadrature error whatever the correct sampler.
EnvironmentMap weighted_map(int w, int h) {
  EnvironmentMap map;
  map.width = w;
  map.height = h;
  map.texels.resize(size_t(w) * size_t(h));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      map.texels[size_t(y) * size_t(w) + size_t(x)] =
          Color(0.5f + 0.02f * x, 0.3f + 0.04f * y, 0.9f - 0.01f * float(x + y)) * float(given_weight(x, y));
  return map;
}

std::vector<Check> probe_build_environment_distribution() {
  std::vector<Check> out;
  const int sizes[][2] = {{32, 16}, {7, 5}};
  for (const auto& s : sizes) {
    const EnvironmentMap map = synthetic_map(s[0], s[1]);
    const EnvironmentDistribution d = build_environment_distribution(map);
    const std::string at = " (" + std::to_string(s[0]) + " x " + std::to_string(s[1]) + " map)";
    add(&out, "build_environment_distribution: width, height, sizes of pdf, marginal_cdf, conditional_cdf" + at,
        {double(d.width), double(d.height), double(d.pdf.size()), double(d.marginal_cdf.size()),
         double(d.conditional_cdf.size())},
        0.0, 0.0);
    add(&out, "build_environment_distribution: pdf of every texel" + at,
        std::vector<double>(d.pdf.begin(), d.pdf.end()), 1e-7, 1e-4);
    add(&out, "build_environment_distribution: marginal_cdf" + at,
        std::vector<double>(d.marginal_cdf.begin(), d.marginal_cdf.end()), 2e-6, 0.0);
    add(&out, "build_environment_distribution: conditional_cdf of every texel" + at,
        std::vector<double>(d.conditional_cdf.begin(), d.conditional_cdf.end()), 2e-6, 0.0);
  }
  EnvironmentMap black;
  black.width = 8;
  black.height = 4;
  black.texels.assign(32, Color(0.0f));
  const EnvironmentDistribution d = build_environment_distribution(black);
  add(&out, "build_environment_distribution: a black map gives empty distributions (1 = empty)",
      {d.empty() ? 1.0 : 0.0}, 0.0, 0.0);
  return out;
}

// Directions over the sphere (off the texel edges' exact angles), and the poles.
std::vector<Vec3> sphere_dirs() {
  std::vector<Vec3> ds;
  for (int i = 0; i < 23; ++i)
    for (int j = 0; j < 19; ++j) {
      const float theta = 0.06f + (kPi - 0.12f) * (i + 0.37f) / 23.0f;
      const float phi = 2.0f * kPi * (j + 0.61f) / 19.0f;
      ds.push_back(angles_to_direction(theta, phi));
    }
  ds.push_back(Vec3(0.0f, 1.0f, 0.0f));
  ds.push_back(Vec3(0.0f, -1.0f, 0.0f));
  return ds;
}

std::vector<Check> probe_environment_pdf() {
  std::vector<Check> out;
  // The build's own distribution of the map: a wrong one makes these
  // checks disagree too, and the hints then name
  // build_environment_distribution first (it is their callee).
  const EnvironmentMap map = synthetic_map(32, 16);
  const EnvironmentDistribution d = build_environment_distribution(map);
  std::vector<double> v;
  for (const Vec3& wi : sphere_dirs()) v.push_back(environment_pdf(d, map, wi));
  add(&out, "environment_pdf: pdf of 439 directions (the last two the poles), with the map's own distribution", v, 1e-5,
      2e-4);
  const EnvironmentDistribution empty;
  add(&out, "environment_pdf: empty distributions give 0",
      {environment_pdf(empty, map, Vec3(0.6f, 0.0f, 0.8f)), environment_pdf(empty, map, Vec3(0.0f, 0.6f, -0.8f))});
  return out;
}

// Over a 64 x 64 grid of (u1, u2) with a given distribution: the fraction
// of samples bringing no light, the mean radiance / pdf (the map's
// integral, estimated), the mean direction, the fraction in 4 polar bands
// x 4 azimuth sectors (whole texels: 4 rows x 8 columns each), and the
// fraction whose pdf differs by over 1e-3 from environment_pdf(wi) (loose:
// computing the density of the texel chosen is legal too). The inversion
// of the CDFs is nearly unique; what a correct sampler may change (ties,
// the point within the texel) moves these by well under the tolerances
// (abs 1e-2 on fractions and directions, rel 1e-2 on the integral).
std::vector<Check> probe_sample_environment() {
  std::vector<Check> out;
  constexpr int N = 64;
  const EnvironmentMap map = weighted_map(32, 16);
  const EnvironmentDistribution d = build_environment_distribution(map);
  int n_dark = 0, n_bad_pdf = 0, n_off = 0;
  double max_unit = 0;
  Vec3d sum_est, sum_wi;
  std::vector<double> hist(16, 0.0);
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j) {
      const LightSample s = sample_environment(d, map, (i + 0.5f) / N, (j + 0.5f) / N);
      max_unit = std::fmax(max_unit, std::fabs(double(norm(s.wi)) - 1.0));
      sum_wi += Vec3d(s.wi);
      float theta = 0, phi = 0;
      direction_to_angles(s.wi, &theta, &phi);
      const int band = std::min(3, std::max(0, int(theta / kPi * 4.0f)));
      const int sector = std::min(3, std::max(0, int(phi / (2.0f * kPi) * 4.0f)));
      hist[size_t(band * 4 + sector)] += 1.0 / (N * N);
      if (!(s.pdf > 0) || !std::isfinite(s.pdf)) {
        ++n_bad_pdf;
        continue;
      }
      if (is_black(s.radiance)) {
        ++n_dark;
        continue;
      }
      sum_est += Vec3d(s.radiance) / double(s.pdf);
      const double p2 = environment_pdf(d, map, s.wi);
      if (!(std::fabs(p2 - s.pdf) <= 1e-3 * std::fabs(p2))) ++n_off;
    }
  add(&out, "sample_environment: fraction with pdf <= 0, fraction bringing no light",
      {double(n_bad_pdf) / (N * N), double(n_dark) / (N * N)}, 1e-2, 0.0);
  {
    std::vector<double> v;
    put(&v, sum_est / double(N * N));
    add(&out, "sample_environment: mean radiance / pdf (the map's integral)", v, 1e-3, 1e-2);
  }
  {
    std::vector<double> v;
    put(&v, sum_wi / double(N * N));
    v.push_back(max_unit);
    add(&out, "sample_environment: mean wi, and max ||wi| - 1|", v, 1e-2, 0.0);
  }
  add(&out, "sample_environment: fraction in 4 polar bands x 4 azimuth sectors", hist, 1e-2, 0.0);
  add(&out, "sample_environment: fraction whose pdf differs from environment_pdf(wi)", {double(n_off) / (N * N)},
      2e-2, 0.0);
  const EnvironmentDistribution empty;
  const LightSample s = sample_environment(empty, map, 0.3f, 0.7f);
  add(&out, "sample_environment: empty distributions give radiance 0, pdf 1",
      {s.radiance.x, s.radiance.y, s.radiance.z, s.pdf});
  return out;
}

// ---------------------------------------------------------------- part 9

// For cameras turned away from the world's axes, lens radii 0, 0.2, 0.5
// and focal distances 2 and 5, per image point over a 128 x 128 grid of
// (u1, u2): where the rays cross the plane of focus (the plane at
// focal_distance along the view direction): their mean point and the
// largest distance from it (any correct lens focuses an image point's rays
// at one point: abs 1e-4); the lens offsets (origin - position in the
// camera's axes): mean (0 for any uniform disk: abs 1e-3 R) and mean
// squared length / R^2 (1/2 for a uniform disk; the concentric map's grid
// gives 1/2 within 1e-4: rel 1e-2); the fraction of origins in 2 rings
// (split at R / sqrt 2) x 4 quadrants (1/8 each; the concentric map's grid
// is within 5e-3 of it: abs 2e-2); max ||d| - 1|; min_t, max_t. With
// radius 0 the ray is fixed: origin and direction (exact).
std::vector<Check> probe_thin_lens() {
  std::vector<Check> out;
  constexpr int N = 128;
  struct Setup {
    Vec3d pos, at, up;
  };
  const Setup setups[] = {{Vec3d(1.0, 2.0, 3.0), Vec3d(-2.0, 0.5, -1.0), Vec3d(0.0, 1.0, 0.0)},
                          {Vec3d(-0.5, 0.3, 0.2), Vec3d(2.0, 3.0, 1.5), Vec3d(0.2, 0.1, 1.0)}};
  const double points[][2] = {{0.5, 0.5}, {0.1, 0.9}, {0.8, 0.25}, {0.0, 0.0}, {1.0, 1.0}};
  int cam_index = 0;
  for (const Setup& s : setups) {
    for (double radius : {0.0, 0.2, 0.5})
      for (double focal : {2.0, 5.0}) {
        Camera cam;
        cam.look_at(s.pos, s.at, s.up);
        cam.hfov_deg = cam_index == 0 ? 50.0 : 70.0;
        cam.vfov_deg = cam_index == 0 ? 37.5 : 40.0;
        cam.near_clip = 0.01;
        cam.far_clip = 250.0;
        cam.lens_radius = radius;
        cam.focal_distance = focal;
        const std::string what = " (camera " + std::to_string(cam_index) + ", lens radius " +
                                 std::to_string(radius) + ", focal distance " + std::to_string(focal) + ")";
        const Vec3d view = -cam.axis_z;  // bookkeeping: the camera's own axes
        const Vec3d plane_point = cam.position + view * focal;
        if (radius == 0.0) {
          std::vector<double> v;
          for (const auto& p : points) {
            const Ray r = generate_ray_for_thin_lens(cam, p[0], p[1], 0.37, 0.81);
            put(&v, r.o);
            put(&v, r.d);
            v.push_back(r.min_t);
            v.push_back(r.max_t);
          }
          add(&out, "generate_ray_for_thin_lens: origin, direction, min_t, max_t of a pinhole" + what, v, 2e-5,
              1e-4);
          continue;
        }
        std::vector<double> focus, lens, rings, misc;
        for (const auto& p : points) {
          std::vector<Vec3d> hits;
          hits.reserve(N * N);
          Vec3d sum_hit, sum_off;
          double sum_r2 = 0, max_unit = 0, min_t = 1e30, max_t = -1e30;
          std::vector<double> ring(8, 0.0);
          for (int i = 0; i < N; ++i)
            for (int j = 0; j < N; ++j) {
              const Ray r = generate_ray_for_thin_lens(cam, p[0], p[1], (i + 0.5) / N, (j + 0.5) / N);
              const Vec3d o(r.o), dir(r.d);
              const double t = dot(plane_point - o, view) / dot(dir, view);
              const Vec3d hit = o + dir * t;
              hits.push_back(hit);
              sum_hit += hit;
              const Vec3d rel = o - cam.position;
              const Vec3d off(dot(rel, cam.axis_x), dot(rel, cam.axis_y), dot(rel, cam.axis_z));
              sum_off += off;
              sum_r2 += dot(off, off);
              const double rr = std::sqrt(off.x * off.x + off.y * off.y) / radius;
              const int q = (off.x >= 0 ? 0 : 1) + (off.y >= 0 ? 0 : 2);
              ring[size_t((rr < std::sqrt(0.5) ? 0 : 4) + q)] += 1.0 / (N * N);
              max_unit = std::fmax(max_unit, std::fabs(norm(dir) - 1.0));
              min_t = std::fmin(min_t, double(r.min_t));
              max_t = std::fmax(max_t, double(r.max_t));
            }
          const Vec3d mean_hit = sum_hit / double(N * N);
          double spread = 0;
          for (const Vec3d& h : hits) spread = std::fmax(spread, norm(h - mean_hit));
          put(&focus, mean_hit);
          focus.push_back(spread);
          put(&lens, sum_off / (double(N * N) * radius));
          lens.push_back(sum_r2 / (double(N * N) * radius * radius));
          rings.insert(rings.end(), ring.begin(), ring.end());
          misc.push_back(max_unit);
          misc.push_back(min_t);
          misc.push_back(max_t);
        }
        add(&out, "generate_ray_for_thin_lens: per image point, mean crossing of the plane of focus and max distance "
                  "from it" + what,
            focus, 1e-4, 1e-4);
        add(&out, "generate_ray_for_thin_lens: per image point, mean lens offset / R (camera axes) and mean squared "
                  "offset / R^2" + what,
            lens, 1e-3, 1e-2);
        add(&out, "generate_ray_for_thin_lens: per image point, fraction of origins per ring (r < R / sqrt 2, "
                  "outside) x quadrant" + what,
            rings, 2e-2, 0.0);
        add(&out, "generate_ray_for_thin_lens: per image point, max ||d| - 1|, min_t, max_t" + what, misc, 1e-5,
            1e-5);
      }
    ++cam_index;
  }
  return out;
}

}  // namespace

std::vector<FunctionProbe> probes_parts_3_6_9() {
  return {
      {"diffuse_f", 3, probe_diffuse_f},
      {"reflect", 6, probe_reflect},
      {"refract", 6, probe_refract},
      {"schlick_reflectance", 6, probe_schlick},
      {"mirror_sample_f", 6, probe_mirror_sample_f},
      {"refraction_sample_f", 6, probe_refraction_sample_f},
      {"glass_sample_f", 6, probe_glass_sample_f},
      {"microfacet_D", 7, probe_microfacet_D},
      {"microfacet_F", 7, probe_microfacet_F},
      {"microfacet_f", 7, probe_microfacet_f},
      {"microfacet_sample_f", 7, probe_microfacet_sample_f},
      {"microfacet_pdf", 7, probe_microfacet_pdf},
      {"build_environment_distribution", 8, probe_build_environment_distribution},
      {"sample_environment", 8, probe_sample_environment},
      {"environment_pdf", 8, probe_environment_pdf},
      {"generate_ray_for_thin_lens", 9, probe_thin_lens},
  };
}

}  // namespace pt::probe
