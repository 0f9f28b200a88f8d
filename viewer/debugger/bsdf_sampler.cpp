// The BSDF sampler: many calls of a material's sample_f from one point and
// one outgoing direction, and whether the directions drawn follow the pdf
// the BSDF reports (a histogram over theta against the pdf's integral), or,
// for a delta BSDF, which directions it chose and how often.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "common/bsdf.h"
#include "common/frame.h"
#include "common/rng.h"
#include "pathtracer/radiance.h"
#include "stages/part1_raytracing/camera_rays.h"
#include "viewer/debugger/debugger.h"
#include "viewer/debugger/json_values.h"
#include "viewer/debugger/todo_collector.h"

namespace pt::debug {

namespace {

constexpr int kBinsPerHemisphere = 30;  // 3 degrees each
// The midpoint grid that integrates the pdf over a bin: fine enough for the
// narrowest lobe of the project's scenes (alpha 0.05, a few degrees wide).
constexpr int kThetaSteps = 12, kPhiSteps = 720;

bool same_bits(const Vec3& a, const Vec3& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

double binomial_z(double count, double expected, double n) {
  const double var = expected * (1 - expected / n);
  return var > 0 ? (count - expected) / std::sqrt(var) : (count == expected ? 0 : INFINITY);
}

// n times the integral of the model's pdf over theta in [lo, hi] (radians).
double expected_count(const Material& m, const Vec3& wo, double lo, double hi, int n) {
  const double dt = (hi - lo) / kThetaSteps, dp = 2 * kPi / kPhiSteps;
  double sum = 0;
  for (int i = 0; i < kThetaSteps; ++i) {
    const double theta = lo + (i + 0.5) * dt, st = std::sin(theta), ct = std::cos(theta);
    double ring = 0;
    for (int j = 0; j < kPhiSteps; ++j) {
      const double phi = (j + 0.5) * dp;
      ring += bsdf_pdf(m, wo, Vec3(float(st * std::cos(phi)), float(st * std::sin(phi)), float(ct)));
    }
    sum += ring * st;
  }
  return sum * dt * dp * n;
}

void histogram(const Material& m, BsdfSamplesResult& r) {
  const int n = int(r.samples.size());
  const double bin = kPi / (2 * kBinsPerHemisphere);
  std::vector<int> counts(2 * kBinsPerHemisphere, 0);
  for (const BsdfSampleTest& s : r.samples) {
    if (!(s.pdf > 0)) continue;
    const double theta = std::acos(std::clamp(double(s.wi_local.z), -1.0, 1.0));
    counts[std::min(2 * kBinsPerHemisphere - 1, int(theta / bin))] += 1;
  }
  std::vector<double> expected(counts.size());
  for (size_t i = 0; i < counts.size(); ++i) expected[i] = expected_count(m, r.wo_local, i * bin, (i + 1) * bin, n);
  double below = 0;
  int below_count = 0;
  for (size_t i = kBinsPerHemisphere; i < counts.size(); ++i) below += expected[i], below_count += counts[i];
  // Only the hemisphere above when nothing (drawn or by the pdf) goes below.
  const size_t bins = below > 0 || below_count > 0 ? counts.size() : size_t(kBinsPerHemisphere);
  r.pdf_integral = 0;
  for (double e : expected) r.pdf_integral += e / n;
  r.agrees = true;
  for (size_t i = 0; i < bins; ++i) {
    BsdfHistogramBin b;
    b.theta_lo = float(i * 3);
    b.theta_hi = float((i + 1) * 3);
    b.count = counts[i];
    b.expected = expected[i];
    const double solid = 2 * kPi * (std::cos(i * bin) - std::cos((i + 1) * bin));
    b.sampled_density = b.count / (n * solid);
    b.pdf_density = b.expected / (n * solid);
    b.z = binomial_z(b.count, b.expected, n);
    b.judged = b.expected >= kBsdfMinExpected;
    if (b.judged && !(std::fabs(b.z) <= kBsdfZBound)) r.agrees = false;
    if (!b.judged) r.pooled_count += b.count, r.pooled_expected += b.expected;
    r.histogram.push_back(b);
  }
  r.pooled_z = binomial_z(r.pooled_count, r.pooled_expected, n);
  // The pool is judged whatever its size: directions drawn where the pdf
  // has (almost) no mass are the bug it catches (|z| infinite at none).
  if (!(std::fabs(r.pooled_z) <= kBsdfZBound)) r.agrees = false;
  int mismatched = 0;
  for (const BsdfHistogramBin& b : r.histogram)
    mismatched += b.judged && !(std::fabs(b.z) <= kBsdfZBound) ? 1 : 0;
  if (r.agrees)
    r.verdict = "the directions follow the pdf: every bin within " + json_number(kBsdfZBound) + " standard deviations";
  else if (r.pooled_expected == 0 && r.pooled_count > 0)
    r.verdict = std::to_string(r.pooled_count) + " direction(s) drawn where the pdf is 0";
  else
    r.verdict = "the directions do not follow the pdf: " + std::to_string(mismatched) + " bin(s)" +
                (std::fabs(r.pooled_z) > kBsdfZBound ? " and the pool of small bins" : "") + " beyond " +
                json_number(kBsdfZBound) + " standard deviations";
}

void delta_directions(BsdfSamplesResult& r) {
  const int n = int(r.samples.size());
  for (const BsdfSampleTest& s : r.samples) {
    if (!(s.pdf > 0)) continue;
    auto it = std::find_if(r.directions.begin(), r.directions.end(),
                           [&](const BsdfDirection& d) { return same_bits(d.wi_local, s.wi_local); });
    if (it == r.directions.end()) {
      BsdfDirection d;
      d.wi_local = s.wi_local;
      d.wi = s.wi;
      d.scatter = (s.wi_local.z > 0) == (r.wo_local.z > 0) ? "reflected" : "refracted";
      d.pdf = s.pdf;
      d.f = s.f;
      d.weight = s.f * (std::fabs(s.wi_local.z) / s.pdf);
      const Vec3& wo = r.wo_local;
      if (d.scatter == "reflected")
        d.mirror_error = norm(s.wi_local - Vec3(-wo.x, -wo.y, wo.z));
      else
        d.sine_ratio = std::sqrt(std::max(0.0f, 1 - wo.z * wo.z)) /
                       std::sqrt(std::max(0.0f, 1 - s.wi_local.z * s.wi_local.z));
      r.directions.push_back(d);
      it = r.directions.end() - 1;
    }
    it->count += 1;
  }
  r.agrees = r.directions.size() <= 2;
  for (BsdfDirection& d : r.directions) {
    d.z = binomial_z(d.count, double(n) * d.pdf, n);
    if (!(std::fabs(d.z) <= kBsdfZBound)) r.agrees = false;
  }
  if (r.directions.size() > 2)
    r.verdict = std::to_string(r.directions.size()) + " different directions from one wo: a delta BSDF has at most two";
  else if (r.agrees)
    r.verdict = "each direction is chosen as often as its reported probability says (within " +
                json_number(kBsdfZBound) + " standard deviations)";
  else
    r.verdict = "a direction is chosen more or less often than its reported probability says";
}

}  // namespace

BsdfSamplesResult sample_bsdf_many(const Material& m, const Vec3& point, const Vec3& normal, const Vec3& wo, int n,
                                   uint64_t seed) {
  for (const Vec3* v : {&point, &normal, &wo})
    if (!std::isfinite(v->x) || !std::isfinite(v->y) || !std::isfinite(v->z))
      throw InputError("the point, the normal and wo must be three finite numbers each");
  if (!(norm2(normal) > 0) || !(norm2(wo) > 0)) throw InputError("the normal and wo must be non-zero vectors");
  if (n < 1 || n > kMaxBsdfSamples)
    throw InputError("the number of samples must be from 1 to " + std::to_string(kMaxBsdfSamples));
  BsdfSamplesResult r;
  r.model = bsdf_model(m).name;
  r.delta = bsdf_is_delta(m);
  r.point = point;
  r.normal = normalize(normal);
  r.wo = normalize(wo);
  r.seed = seed;
  const Frame frame = Frame::from_normal(r.normal);
  r.wo_local = frame.to_local(r.wo);
  r.samples.reserve(size_t(n));
  TodoCollector todos;
  {
    ScopedPathRecorder install(&todos);
    Rng rng(seed);
    try {
      for (int i = 0; i < n; ++i) {
        BsdfSampleTest t;
        t.u1 = rng.uniform();
        t.u2 = rng.uniform();
        t.f = bsdf_sample_f(m, r.wo_local, t.u1, t.u2, &t.wi_local, &t.pdf);
        t.wi = frame.to_world(t.wi_local);
        if (!r.delta && t.pdf > 0) {
          t.pdf_model = bsdf_pdf(m, r.wo_local, t.wi_local);
          if (!(std::fabs(t.pdf_model - t.pdf) <= 1e-3f * std::max(t.pdf, t.pdf_model))) ++r.pdf_mismatches;
        }
        r.no_direction += t.pdf > 0 ? 0 : 1;
        r.samples.push_back(t);
      }
      if (r.delta)
        delta_directions(r);
      else
        histogram(m, r);
    } catch (const std::exception& e) {
      r.error = std::string("sample_f or pdf of the ") + r.model + " BSDF: " + e.what();
    }
  }
  r.todos = todos.todos;
  return r;
}

BsdfSamplesResult sample_bsdf_at_pixel(const Scene& scene, const Intersector& geometry, const RenderOptions& opts,
                                       int x, int y, int n, uint64_t seed) {
  if (x < 0 || y < 0 || x >= opts.width || y >= opts.height)
    throw InputError("pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") is outside the " +
                     std::to_string(opts.width) + "x" + std::to_string(opts.height) + " image");
  Ray ray;
  Hit hit;
  bool found = false;
  TodoCollector todos;
  {
    ScopedPathRecorder install(&todos);
    ray = generate_ray(scene.camera, (x + 0.5) / opts.width, (y + 0.5) / opts.height);
    found = geometry.intersect(ray, &hit);
  }
  if (!todos.todos.empty()) {
    BsdfSamplesResult r;
    r.todos = todos.todos;
    r.error = "no hit to sample from: the camera ray or the intersection code is not written yet";
    return r;
  }
  if (!found)
    throw InputError("the camera ray through pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                     ") hits nothing: pick a pixel on a surface");
  const std::shared_ptr<const PartShading> shading = part_shading(scene, opts.part, opts.bsdf_hemisphere);
  static const Material fallback;
  const bool known = hit.material >= 0 && size_t(hit.material) < shading->materials.size();
  const Material& m = known ? shading->materials[size_t(hit.material)] : fallback;
  BsdfSamplesResult r = sample_bsdf_many(m, ray.at(hit.t), hit.n, -ray.d, n, seed);
  r.material = hit.material;
  r.material_name = (m.name.empty() ? "material " + std::to_string(hit.material) : m.name) + " (" +
                    to_string(m.type) + ")";
  return r;
}

// One line per sample: a call may take 65,536.
Json BsdfSampleTest::json() const {
  Json o = json_object(true);
  o.set("u", json_pair(u1, u2))
      .set("wi_local", json_vec(wi_local))
      .set("wi", json_vec(wi))
      .set("f", json_vec(f))
      .set("pdf", json_float(pdf))
      .set("pdf_model", json_float(pdf_model));
  return o;
}

Json BsdfHistogramBin::json() const {
  Json o = json_object(true);
  o.set("theta", json_pair(theta_lo, theta_hi))
      .set("count", json_int(count))
      .set("expected", json_real(expected))
      .set("sampled_density", json_real(sampled_density))
      .set("pdf_density", json_real(pdf_density))
      .set("z", json_real(z))
      .set("judged", json_bool(judged));
  return o;
}

Json BsdfDirection::json() const {
  Json o = json_object(true);
  o.set("wi_local", json_vec(wi_local))
      .set("wi", json_vec(wi))
      .set("scatter", json_text(scatter))
      .set("count", json_int(count))
      .set("pdf", json_float(pdf))
      .set("f", json_vec(f))
      .set("weight", json_vec(weight))
      .set("z", json_real(z));
  if (scatter == "reflected")
    o.set("mirror_error", json_float(mirror_error));
  else
    o.set("sine_ratio", json_float(sine_ratio));
  return o;
}

Json BsdfSamplesResult::json() const {
  std::vector<Json> items;
  items.reserve(samples.size());
  for (const BsdfSampleTest& s : samples) items.push_back(s.json());
  Json o = json_object();
  o.set("material", json_int(material))
      .set("material_name", json_text(material_name))
      .set("model", json_text(model))
      .set("delta", json_bool(delta))
      .set("point", json_vec(point))
      .set("normal", json_vec(normal))
      .set("wo", json_vec(wo))
      .set("wo_local", json_vec(wo_local))
      .set("seed", json_seed(seed))
      .set("no_direction", json_int(no_direction));
  if (delta) {
    std::vector<Json> dirs;
    for (const BsdfDirection& d : directions) dirs.push_back(d.json());
    o.set("directions", json_list(std::move(dirs)));
  } else {
    std::vector<Json> bins;
    for (const BsdfHistogramBin& b : histogram) bins.push_back(b.json());
    o.set("histogram", json_list(std::move(bins)))
        .set("pdf_integral", json_real(pdf_integral))
        .set("pooled", json_object(true)
                           .set("count", json_int(pooled_count))
                           .set("expected", json_real(pooled_expected))
                           .set("z", json_real(pooled_z)))
        .set("pdf_mismatches", json_int(pdf_mismatches));
  }
  o.set("z_bound", json_real(kBsdfZBound)).set("min_expected", json_real(kBsdfMinExpected));
  o.set("agrees", json_bool(agrees)).set("verdict", json_text(verdict));
  o.set("samples", json_list(std::move(items))).set("todos", json_strings(todos));
  if (!error.empty()) o.set("error", json_text(error));
  return o;
}

}  // namespace pt::debug
