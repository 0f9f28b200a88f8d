// The function checks of part 3's light estimators and part 4's path
// (probe.h): they need a scene.
//
// The scene is built here in memory: an open-fronted box of diffuse walls
// (each its own albedo), an emissive quad in the ceiling that is also the
// scene's main area light, a small emissive quad on the left wall (a second
// area light), a point light, a directional light and an ambient sky seen
// through the open front, a block on the floor that shadows part of it and
// a sphere. Geometry is traced by testing every primitive (the given
// BruteForceIntersector over part 1's intersect_triangle and
// intersect_sphere): no BVH is involved.
//
// The checks call the student functions and report what they return; the
// expected figures are the reference build's, never computed here.
// zero_bounce_radiance is a function of its inputs: compared to float
// round-off. The estimators are Monte-Carlo: correct implementations
// differ in how they use their random numbers and in their variance
// (multiple importance sampling, other Russian-roulette probabilities, ...),
// so each check reports the MEAN of many calls at one shading point, with
// a tolerance computed in the same run from the calls' own spread: 6
// sqrt(2) standard errors of the mean (the difference of two independent
// correct means has sqrt(2) the standard error of one), plus a small
// floor. The largest standard error of the three colour channels is used
// for all three.
#include "pathtracer/probe.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "common/intersector.h"
#include "common/lights.h"
#include "common/ray.h"
#include "common/rng.h"
#include "common/scene.h"
#include "stages/part1_raytracing/brute_force.h"
#include "stages/part3_direct_lighting/direct_lighting.h"
#include "stages/part4_global_illumination/global_illumination.h"

namespace pt::probe {

namespace {

void push3(std::vector<double>* v, const Vec3& p) {
  v->push_back(p.x);
  v->push_back(p.y);
  v->push_back(p.z);
}

// A quad of two triangles: corner `a`, sides `u` and `v`, both triangles
// with the flat normal `n` (the side it faces is chosen here, not by the
// winding).
void add_quad(Scene* s, const Vec3& a, const Vec3& u, const Vec3& v, const Vec3& n, int material) {
  const Vec3 nn = normalize(n);
  Triangle t1, t2;
  t1.p1 = a, t1.p2 = a + u, t1.p3 = a + u + v;
  t2.p1 = a, t2.p2 = a + u + v, t2.p3 = a + v;
  t1.n1 = t1.n2 = t1.n3 = nn;
  t2.n1 = t2.n2 = t2.n3 = nn;
  t1.material = t2.material = material;
  s->triangles.push_back(t1);
  s->triangles.push_back(t2);
}

Material diffuse(const Color& albedo) {
  Material m;
  m.type = MaterialType::Diffuse;
  m.albedo = albedo;
  return m;
}

Material emissive(const Color& e) {
  Material m;
  m.type = MaterialType::Emission;
  m.albedo = Color(0.0f);
  m.emission = e;
  return m;
}

enum Mat { kFloor, kCeiling, kLeft, kRight, kBack, kBlock, kSphere, kLightA, kLightB, kCard, kNumMats };

// The box spans x in [-1, 1], y in [0, 2], z in [-1, 1]; its front (z = 1)
// is open to the sky.
Scene lit_box() {
  Scene s;
  s.materials.resize(kNumMats);
  s.materials[kFloor] = diffuse(Color(0.7f, 0.7f, 0.65f));
  s.materials[kCeiling] = diffuse(Color(0.6f, 0.6f, 0.6f));
  s.materials[kLeft] = diffuse(Color(0.65f, 0.1f, 0.1f));
  s.materials[kRight] = diffuse(Color(0.1f, 0.6f, 0.15f));
  s.materials[kBack] = diffuse(Color(0.5f, 0.5f, 0.8f));
  s.materials[kBlock] = diffuse(Color(0.8f, 0.6f, 0.3f));
  s.materials[kSphere] = diffuse(Color(0.3f, 0.5f, 0.7f));
  s.materials[kLightA] = emissive(Color(6.0f, 5.0f, 4.0f));
  s.materials[kLightB] = emissive(Color(2.0f, 4.0f, 8.0f));
  s.materials[kCard] = diffuse(Color(0.9f, 0.8f, 0.7f));
  // Walls, facing into the box.
  add_quad(&s, Vec3(-1, 0, -1), Vec3(2, 0, 0), Vec3(0, 0, 2), Vec3(0, 1, 0), kFloor);
  add_quad(&s, Vec3(-1, 2, -1), Vec3(2, 0, 0), Vec3(0, 0, 2), Vec3(0, -1, 0), kCeiling);
  add_quad(&s, Vec3(-1, 0, -1), Vec3(0, 2, 0), Vec3(0, 0, 2), Vec3(1, 0, 0), kLeft);
  add_quad(&s, Vec3(1, 0, -1), Vec3(0, 2, 0), Vec3(0, 0, 2), Vec3(-1, 0, 0), kRight);
  add_quad(&s, Vec3(-1, 0, -1), Vec3(2, 0, 0), Vec3(0, 2, 0), Vec3(0, 0, 1), kBack);
  // Area light A: just below the ceiling, emitting downward; its quad
  // covers exactly the light's rectangle.
  {
    Light a;
    a.type = LightType::Area;
    a.radiance = s.materials[kLightA].emission;
    a.position = Vec3(0.0f, 1.98f, 0.0f);
    a.dim_x = Vec3(0.8f, 0, 0);
    a.dim_y = Vec3(0, 0, 0.6f);
    a.direction = Vec3(0, -1, 0);
    s.lights.push_back(a);
    add_quad(&s, a.position - a.dim_x * 0.5f - a.dim_y * 0.5f, a.dim_x, a.dim_y, a.direction, kLightA);
  }
  // Area light B: small, just off the left wall, emitting toward +x.
  {
    Light b;
    b.type = LightType::Area;
    b.radiance = s.materials[kLightB].emission;
    b.position = Vec3(-0.98f, 1.0f, -0.3f);
    b.dim_x = Vec3(0, 0, 0.3f);
    b.dim_y = Vec3(0, 0.3f, 0);
    b.direction = Vec3(1, 0, 0);
    s.lights.push_back(b);
    add_quad(&s, b.position - b.dim_x * 0.5f - b.dim_y * 0.5f, b.dim_x, b.dim_y, b.direction, kLightB);
  }
  {
    Light p;  // a point light with COLLADA attenuation
    p.type = LightType::Point;
    p.radiance = Color(1.5f, 1.5f, 1.2f);
    p.position = Vec3(0.5f, 1.5f, 0.6f);
    p.linear_attenuation = 0.2f;
    s.lights.push_back(p);
  }
  {
    Light d;  // sunlight through the open front
    d.type = LightType::Directional;
    d.radiance = Color(0.5f, 0.45f, 0.4f);
    d.direction = normalize(Vec3(0.2f, -0.5f, -1.0f));
    s.lights.push_back(d);
  }
  {
    Light sky;  // the ambient sky, seen through the open front
    sky.type = LightType::Ambient;
    sky.radiance = Color(0.3f, 0.35f, 0.45f);
    s.lights.push_back(sky);
  }
  // A block on the floor (no bottom face), shadowing part of the floor.
  {
    const float x0 = 0.1f, x1 = 0.5f, y1 = 0.6f, z0 = -0.5f, z1 = -0.1f;
    add_quad(&s, Vec3(x0, y1, z0), Vec3(x1 - x0, 0, 0), Vec3(0, 0, z1 - z0), Vec3(0, 1, 0), kBlock);
    add_quad(&s, Vec3(x0, 0, z1), Vec3(x1 - x0, 0, 0), Vec3(0, y1, 0), Vec3(0, 0, 1), kBlock);
    add_quad(&s, Vec3(x0, 0, z0), Vec3(x1 - x0, 0, 0), Vec3(0, y1, 0), Vec3(0, 0, -1), kBlock);
    add_quad(&s, Vec3(x0, 0, z0), Vec3(0, 0, z1 - z0), Vec3(0, y1, 0), Vec3(-1, 0, 0), kBlock);
    add_quad(&s, Vec3(x1, 0, z0), Vec3(0, 0, z1 - z0), Vec3(0, y1, 0), Vec3(1, 0, 0), kBlock);
  }
  // A free-standing card (a lone quad, lit on one side and seen from both).
  add_quad(&s, Vec3(0.55f, 0.9f, 0.2f), Vec3(0.3f, 0, 0), Vec3(0, 0.4f, 0.25f), Vec3(0, -0.53f, 0.85f), kCard);
  // A sphere floating a little above the floor.
  s.spheres.push_back(Sphere{Vec3(-0.45f, 0.45f, 0.3f), 0.35f, kSphere});
  return s;
}

// A shading point: the ray that found it (max_t = t after the hit) and
// its hit record.
struct ShadingPoint {
  std::string name;
  Ray ray;
  Hit hit;
  bool found = false;
};

ShadingPoint traced(const Intersector& geometry, const std::string& name, const Vec3& eye, const Vec3& target) {
  ShadingPoint s;
  s.name = name;
  s.ray = Ray(eye, normalize(target - eye), 0.0f);
  s.found = geometry.intersect(s.ray, &s.hit);
  return s;
}

// The shading points of the estimators: lit, in partial shadow, on the
// walls, the sphere, the block, the card (both sides), on the light, under
// the sphere (facing away from every light), and one whose shading normal
// leans away from its surface (as smooth normals do), so that some light
// samples lie below it.
std::vector<ShadingPoint> shading_points(const Intersector& g) {
  std::vector<ShadingPoint> pts;
  pts.push_back(traced(g, "floor, lit", Vec3(0, 1, 2.5f), Vec3(-0.1f, 0, 0.1f)));
  pts.push_back(traced(g, "floor beside the block, partly shadowed", Vec3(0.6f, 1.2f, 1.8f), Vec3(0.55f, 0, -0.3f)));
  pts.push_back(traced(g, "floor behind the block", Vec3(0.3f, 1.6f, 0.8f), Vec3(0.3f, 0, -0.75f)));
  pts.push_back(traced(g, "back wall", Vec3(0, 1, 2.5f), Vec3(0.2f, 1.1f, -1)));
  pts.push_back(traced(g, "right wall", Vec3(-0.5f, 1, 2.0f), Vec3(1, 0.8f, -0.2f)));
  pts.push_back(traced(g, "ceiling beside the light", Vec3(0, 0.5f, 1.5f), Vec3(0.7f, 2, -0.5f)));
  pts.push_back(traced(g, "top of the sphere", Vec3(-0.3f, 1.8f, 1.5f), Vec3(-0.45f, 0.8f, 0.3f)));
  pts.push_back(traced(g, "side of the sphere", Vec3(0.5f, 0.5f, 1.8f), Vec3(-0.45f, 0.45f, 0.3f)));
  pts.push_back(traced(g, "underside of the sphere", Vec3(0.4f, 0.02f, 1.2f), Vec3(-0.45f, 0.1f, 0.3f)));
  pts.push_back(traced(g, "top of the block", Vec3(0.3f, 1.8f, 0.9f), Vec3(0.3f, 0.6f, -0.3f)));
  pts.push_back(traced(g, "card, front", Vec3(0.7f, 0.6f, 1.5f), Vec3(0.7f, 1.1f, 0.35f)));
  pts.push_back(traced(g, "card, back", Vec3(0.7f, 1.6f, -0.6f), Vec3(0.7f, 1.1f, 0.35f)));
  pts.push_back(traced(g, "main light, from below", Vec3(0.2f, 0.5f, 0.6f), Vec3(0.1f, 1.98f, 0.05f)));
  {
    ShadingPoint t = traced(g, "floor, shading normal leaning 50 degrees toward +x", Vec3(0, 1, 2.5f),
                            Vec3(-0.6f, 0, 0.4f));
    t.hit.n = normalize(Vec3(0.77f, 0.64f, 0.0f));
    pts.push_back(t);
  }
  return pts;
}

// Means of colours and the standard error of each channel's mean.
struct Mean {
  double s[3] = {0, 0, 0}, ss[3] = {0, 0, 0};
  long n = 0;
  bool finite = true;
  void add(const Color& c) {
    const double v[3] = {c.x, c.y, c.z};
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(v[k])) finite = false;
      s[k] += v[k];
      ss[k] += v[k] * v[k];
    }
    ++n;
  }
  double mean(int k) const { return finite ? s[k] / double(n) : NAN; }
  double se() const {
    double worst = 0;
    for (int k = 0; k < 3; ++k) {
      const double m = s[k] / double(n);
      const double var = std::max(0.0, (ss[k] / double(n) - m * m)) * double(n) / double(n - 1);
      worst = std::max(worst, std::sqrt(var / double(n)));
    }
    return finite ? worst : 0.0;
  }
  // The check's tolerance: `k` sqrt(2) standard errors (6 by default), a
  // floor of 1e-4.
  double tolerance(double k = 6.0) const { return k * std::sqrt(2.0) * se() + 1e-4; }
  std::vector<double> values() const { return {mean(0), mean(1), mean(2)}; }
};

// ---------------------------------------------------------------------------
// Part 3: zero_bounce_radiance (deterministic).
std::vector<Check> probe_zero_bounce_radiance() {
  std::vector<Check> out;
  const Scene s = lit_box();
  const BruteForceIntersector g(s);
  const ShadingContext ctx{ShadingScene(s), g};
  // Rays traced into the box from many points, every hit's answer.
  {
    std::vector<double> v;
    Rng rng(31);
    int hits = 0;
    for (int i = 0; i < 300; ++i) {
      const Vec3 eye(1.8f * rng.uniform() - 0.9f, 0.05f + 1.9f * rng.uniform(), 1.8f * rng.uniform() - 0.9f);
      const float z = 2.0f * rng.uniform() - 1.0f, phi = 6.2831853f * rng.uniform();
      const float rr = std::sqrt(std::max(0.0f, 1.0f - z * z));
      Ray r(eye, Vec3(rr * std::cos(phi), z, rr * std::sin(phi)));
      Hit h;
      if (!g.intersect(r, &h)) continue;
      ++hits;
      push3(&v, zero_bounce_radiance(ctx, r, h));
    }
    add(&out, "zero_bounce_radiance: " + std::to_string(hits) + " hits of rays from points inside the box", v, 1e-6,
        1e-5);
  }
  // The two lights seen from the room (their front) at several angles.
  {
    std::vector<double> v;
    const Vec3 eyes[] = {Vec3(0, 0.1f, 0), Vec3(0.9f, 1.5f, 0.9f), Vec3(-0.8f, 0.3f, -0.8f), Vec3(0.5f, 1.9f, 0.9f)};
    const Vec3 targets[] = {Vec3(0, 1.98f, 0), Vec3(0.3f, 1.98f, 0.2f), Vec3(-0.35f, 1.98f, -0.25f)};
    for (const Vec3& e : eyes)
      for (const Vec3& t : targets) {
        Ray r(e, normalize(t - e));
        Hit h;
        const bool hit = g.intersect(r, &h);
        v.push_back(hit ? 1 : 0);
        push3(&v, hit ? zero_bounce_radiance(ctx, r, h) : Color(-1.0f));
      }
    // The small light from the room (its front). Rays from the narrow gaps
    // behind the lights graze them: where they land is float round-off (a
    // correct double-precision intersector lands elsewhere), so the lights'
    // backs are checked with the made-up hits below instead.
    const Vec3 bt[] = {Vec3(-0.98f, 1.0f, -0.3f), Vec3(-0.98f, 1.1f, -0.2f)};
    for (const Vec3& t : bt) {
      for (const Vec3& e : {Vec3(0.5f, 0.4f, 0.6f), Vec3(-0.2f, 1.0f, -0.3f)}) {
        Ray r(e, normalize(t - e));
        Hit h;
        const bool hit = g.intersect(r, &h);
        v.push_back(hit ? 1 : 0);
        push3(&v, hit ? zero_bounce_radiance(ctx, r, h) : Color(-1.0f));
      }
    }
    add(&out, "zero_bounce_radiance: the two lights seen from the front at several angles", v, 1e-6,
        1e-5);
  }
  // Hit records made here: every material, the normal facing the ray, away
  // from it, and at a grazing angle.
  {
    std::vector<double> v;
    const Vec3 dirs[] = {Vec3(0, -1, 0), Vec3(0, 1, 0), normalize(Vec3(1, -0.2f, 0.3f)), normalize(Vec3(-0.3f, 0.9f, 0.1f))};
    const Vec3 normals[] = {Vec3(0, 1, 0), Vec3(0, -1, 0), normalize(Vec3(0.6f, 0.8f, 0)), Vec3(1, 0, 0)};
    for (int m = 0; m < kNumMats; ++m)
      for (const Vec3& d : dirs)
        for (const Vec3& n : normals) {
          Ray r(Vec3(0.1f, 1.0f, -0.2f), d, 0.0f);
          Hit h;
          h.t = 0.75f;
          r.max_t = h.t;
          h.n = n;
          h.material = m;
          h.primitive = 0;
          push3(&v, zero_bounce_radiance(ctx, r, h));
        }
    add(&out, "zero_bounce_radiance: every material, normals facing toward, away from and across the ray", v, 1e-6,
        1e-5);
  }
  return out;
}

// ---------------------------------------------------------------------------
// Part 3: the two direct-light estimators: the mean of N calls at each
// shading point, for -l 1 and -l 4.
using Estimator = Color (*)(const ShadingContext&, const Ray&, const Hit&, Rng&);

void estimator_means(std::vector<Check>* out, const char* fname, Estimator est, bool hemisphere, int calls_l1,
                     int calls_l4) {
  const Scene s = lit_box();
  const BruteForceIntersector g(s);
  const std::vector<ShadingPoint> pts = shading_points(g);
  for (int l : {1, 4}) {
    ShadingContext ctx{ShadingScene(s), g};
    ctx.light_samples = l;
    ctx.hemisphere = hemisphere;
    const int N = l == 1 ? calls_l1 : calls_l4;
    for (size_t k = 0; k < pts.size(); ++k) {
      const ShadingPoint& p = pts[k];
      if (!p.found) {
        add(out, std::string(fname) + ": " + p.name + ": no hit", {NAN}, 0, 0);
        continue;
      }
      Rng rng(1000 * uint64_t(l) + k);
      Mean m;
      for (int i = 0; i < N; ++i) m.add(est(ctx, p.ray, p.hit, rng));
      add(out,
          std::string(fname) + ": " + p.name + ", -l " + std::to_string(l) + ": mean RGB of " + std::to_string(N) +
              " calls (tolerance 6 sqrt(2) standard errors)",
          m.values(), m.tolerance(), 0);
    }
  }
}

std::vector<Check> probe_estimate_direct_lighting_hemisphere() {
  std::vector<Check> out;
  estimator_means(&out, "estimate_direct_lighting_hemisphere", estimate_direct_lighting_hemisphere, true, 12000,
                  4000);
  return out;
}

// Counts the queries an estimator makes (closest-hit and shadow alike: a
// shadow ray may be cast with either).
class CountingIntersector final : public Intersector {
 public:
  explicit CountingIntersector(const Intersector& inner) : inner_(inner) {}
  bool intersect(Ray& r, Hit* hit) const override {
    ++queries;
    return inner_.intersect(r, hit);
  }
  bool occluded(const Ray& r) const override {
    ++queries;
    return inner_.occluded(r);
  }
  mutable long long queries = 0;

 private:
  const Intersector& inner_;
};

std::vector<Check> probe_estimate_direct_lighting_importance() {
  std::vector<Check> out;
  estimator_means(&out, "estimate_direct_lighting_importance", estimate_direct_lighting_importance, false, 8000,
                  3000);
  // Delta lights only (a point light and a directional one) over a floor
  // with a block: the estimate has no randomness, and each delta light
  // takes one shadow ray whatever -l says (both lights lie above these
  // points and send light, so no sample is skipped before its ray).
  {
    Scene s;
    s.materials.push_back(diffuse(Color(0.7f, 0.6f, 0.5f)));
    s.materials.push_back(diffuse(Color(0.2f, 0.4f, 0.8f)));
    add_quad(&s, Vec3(-2, 0, -2), Vec3(4, 0, 0), Vec3(0, 0, 4), Vec3(0, 1, 0), 0);
    add_quad(&s, Vec3(-0.3f, 0.8f, -0.3f), Vec3(0.6f, 0, 0), Vec3(0, 0, 0.6f), Vec3(0, 1, 0), 1);
    Light p;
    p.type = LightType::Point;
    p.radiance = Color(2.0f, 1.8f, 1.5f);
    p.position = Vec3(0.1f, 2.0f, 0.2f);
    p.quadratic_attenuation = 0.3f;
    s.lights.push_back(p);
    Light d;
    d.type = LightType::Directional;
    d.radiance = Color(0.4f, 0.5f, 0.6f);
    d.direction = normalize(Vec3(-0.4f, -1.0f, 0.3f));
    s.lights.push_back(d);
    const BruteForceIntersector bf(s);
    CountingIntersector g(bf);
    std::vector<double> vals, counts;
    const Vec3 targets[] = {Vec3(1.0f, 0, 0.5f), Vec3(0.05f, 0, 0.1f), Vec3(0.5f, 0, -0.6f), Vec3(-1.2f, 0, 1.3f),
                            Vec3(0, 0.8f, 0)};
    for (int l : {1, 4}) {
      ShadingContext ctx{ShadingScene(s), g};
      ctx.light_samples = l;
      for (const Vec3& t : targets) {
        const Vec3 eye = t + Vec3(0.3f, 2.5f, 1.0f);
        Ray r(eye, normalize(t - eye), 0.0f);
        Hit h;
        if (!bf.intersect(r, &h)) {
          vals.push_back(NAN);
          continue;
        }
        Rng rng(77);
        g.queries = 0;
        const Color L = estimate_direct_lighting_importance(ctx, r, h, rng);
        counts.push_back(double(g.queries));
        push3(&vals, L);
      }
    }
    add(&out, "estimate_direct_lighting_importance: a point and a directional light only, -l 1 and 4: RGB at 5 points",
        vals, 1e-5, 1e-4);
    add(&out,
        "estimate_direct_lighting_importance: rays traced per call with a point and a directional light only "
        "(one per delta light), -l 1 and 4",
        counts, 0.5, 0);
  }
  return out;
}

// ---------------------------------------------------------------------------
// Part 4: at_least_one_bounce_radiance: the mean of N calls at a shading
// point for several path options, with -l 1 light sampling. Correct paths
// may be noisier than the reference's (a bounce sampled uniformly over the
// hemisphere, Russian roulette from the first bounce or with a lower
// probability): 7 sqrt(2) standard errors of the reference's mean.
constexpr double kPathSigmas = 7.0;
std::vector<Check> probe_at_least_one_bounce_radiance() {
  std::vector<Check> out;
  const Scene s = lit_box();
  const BruteForceIntersector g(s);
  const std::vector<ShadingPoint> all = shading_points(g);
  // Floor lit, floor behind the block, back wall, top of the sphere,
  // ceiling (no direct light from the main light: its light is indirect).
  const size_t chosen[] = {0, 2, 3, 5, 6};
  struct Config {
    int max_depth;
    int depth;  // r.depth: max_depth for a camera ray's first hit
    bool accumulate, rr;
    int calls;
    const char* what;
  };
  const Config configs[] = {
      {1, 1, true, true, 2500, "-m 1 -o 1"},
      {1, 1, false, true, 1500, "-m 1 -o 0"},
      {2, 2, true, false, 3000, "-m 2 -o 1 --no-rr"},
      {2, 2, false, false, 3000, "-m 2 -o 0 --no-rr"},
      {4, 4, true, false, 2000, "-m 4 -o 1 --no-rr"},
      {3, 3, false, false, 2500, "-m 3 -o 0 --no-rr"},
      {4, 4, true, true, 3000, "-m 4 -o 1 (Russian roulette)"},
      {3, 3, false, true, 10000, "-m 3 -o 0 (Russian roulette)"},
      // A vertex past the first bounce: its bounce plays Russian roulette,
      // and with -o 0 only the light that bounce brings counts.
      {5, 2, false, true, 30000, "-m 5 -o 0, a later vertex (r.depth 2, Russian roulette)"},
      {5, 3, true, true, 3000, "-m 5 -o 1, a later vertex (r.depth 3, Russian roulette)"},
  };
  ShadingContext ctx{ShadingScene(s), g};
  ctx.light_samples = 1;
  ctx.hemisphere = false;
  for (size_t c = 0; c < sizeof configs / sizeof configs[0]; ++c) {
    const Config& cf = configs[c];
    PathOptions opts;
    opts.max_depth = cf.max_depth;
    opts.accumulate = cf.accumulate;
    opts.russian_roulette = cf.rr;
    opts.skip_direct = false;
    for (size_t k : chosen) {
      const ShadingPoint& p = all[k];
      if (!p.found) {
        add(&out, std::string("at_least_one_bounce_radiance: ") + p.name + ": no hit", {NAN}, 0, 0);
        continue;
      }
      Ray r = p.ray;
      r.depth = cf.depth;
      Rng rng(5000 + 100 * c + k);
      Mean m;
      for (int i = 0; i < cf.calls; ++i) m.add(at_least_one_bounce_radiance(ctx, opts, r, p.hit, rng));
      add(&out,
          std::string("at_least_one_bounce_radiance: ") + cf.what + ", " + p.name + ": mean RGB of " +
              std::to_string(cf.calls) + " calls (tolerance 7 sqrt(2) standard errors)",
          m.values(), m.tolerance(kPathSigmas), 0);
    }
  }
  // -l 4 and -H: the direct light of each vertex through the other
  // estimator settings.
  {
    ShadingContext c4 = ctx;
    c4.light_samples = 4;
    ShadingContext ch = ctx;
    ch.hemisphere = true;
    PathOptions opts;
    opts.max_depth = 2;
    opts.accumulate = true;
    opts.russian_roulette = false;
    for (const ShadingContext* cx : {&c4, &ch}) {
      for (size_t k : {size_t(0), size_t(3)}) {
        const ShadingPoint& p = all[k];
        if (!p.found) continue;
        Ray r = p.ray;
        r.depth = 2;
        Rng rng(9000 + k + (cx == &ch ? 50 : 0));
        Mean m;
        const int N = cx == &ch ? 4000 : 1500;
        for (int i = 0; i < N; ++i) m.add(at_least_one_bounce_radiance(*cx, opts, r, p.hit, rng));
        add(&out,
            std::string("at_least_one_bounce_radiance: -m 2 -o 1 --no-rr ") + (cx == &ch ? "-H" : "-l 4") + ", " +
                p.name + ": mean RGB of " + std::to_string(N) + " calls",
            m.values(), m.tolerance(kPathSigmas), 0);
      }
    }
  }
  return out;
}

}  // namespace

std::vector<FunctionProbe> probes_lighting() {
  return {
      {"zero_bounce_radiance", 3, probe_zero_bounce_radiance},
      {"estimate_direct_lighting_hemisphere", 3, probe_estimate_direct_lighting_hemisphere},
      {"estimate_direct_lighting_importance", 3, probe_estimate_direct_lighting_importance},
      {"at_least_one_bounce_radiance", 4, probe_at_least_one_bounce_radiance},
  };
}

}  // namespace pt::probe
