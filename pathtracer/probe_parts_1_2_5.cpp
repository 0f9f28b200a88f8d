// The function checks of parts 1, 2 and 5 (probe.h).
//
// Each check calls a student function on fixed inputs and reports what it
// returned; the expected figures are the reference build's, never computed
// here. Functions that are fixed by their inputs are compared to float
// round-off; those whose use of random numbers is the student's choice are
// compared by statistics with tolerances of several standard errors (the
// reasoning is next to each check).
#include "pathtracer/probe.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <set>
#include <tuple>
#include <vector>

#include "common/camera.h"
#include "common/ray.h"
#include "common/rng.h"
#include "common/scene.h"
#include "common/stats.h"
#include "stages/part1_raytracing/camera_rays.h"
#include "stages/part1_raytracing/pixel_sampling.h"
#include "stages/part1_raytracing/sphere.h"
#include "stages/part1_raytracing/triangle.h"
#include "stages/part2_bvh/bvh.h"
#include "stages/part2_bvh/slab_test.h"
#include "stages/part5_adaptive_sampling/adaptive_sampling.h"

namespace pt::probe {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr float kInf = std::numeric_limits<float>::infinity();

void push3(std::vector<double>* v, const Vec3& p) {
  v->push_back(p.x);
  v->push_back(p.y);
  v->push_back(p.z);
}

// ---------------------------------------------------------------------------
// Cameras: the default one, and cameras whose axes are not the world's, with
// other fields of view and non-square images.
std::vector<Camera> test_cameras() {
  std::vector<Camera> cams;
  Camera a;  // default: 800x600, looking down -z from the origin
  cams.push_back(a);
  Camera b;
  b.look_at(Vec3d(1, 2, 3), Vec3d(-0.5, 0.3, -1), Vec3d(0, 1, 0));
  b.set_resolution(320, 180);
  b.near_clip = 0.01;
  b.far_clip = 50;
  cams.push_back(b);
  Camera c;
  c.look_at(Vec3d(-2, 0.5, 1), Vec3d(1, -1, 0.5), Vec3d(0.2, 1, 0.1));
  c.hfov_deg = 70;
  c.vfov_deg = 30;
  c.width = 64;
  c.height = 48;
  c.near_clip = 0.5;
  c.far_clip = 20;
  cams.push_back(c);
  Camera d;  // looking straight down: look_at's fallback for the up vector
  d.look_at(Vec3d(0.3, 5, -0.2), Vec3d(0.3, 0, -0.2), Vec3d(0, 1, 0));
  d.hfov_deg = 20;
  d.vfov_deg = 45;
  d.width = 30;
  d.height = 70;
  cams.push_back(d);
  return cams;
}

// A 4 x 2 image whose sensor spans [-2, 2] x [-1, 1] at z = -1, looking down
// -z: for pixel (2, 1), d.x / -d.z and d.y / -d.z are where the ray crosses
// the pixel, in pixel units from its bottom-left corner (the header's
// contract for the sensor). Film offsets of jittered samples are read this
// way.
Camera film_camera() {
  Camera c;
  c.hfov_deg = 2.0 * std::atan(2.0) * 180.0 / kPi;
  c.vfov_deg = 90.0;
  c.width = 4;
  c.height = 2;
  return c;
}

double film_u(const Ray& r) { return double(r.d.x) / double(-r.d.z); }
double film_v(const Ray& r) { return double(r.d.y) / double(-r.d.z); }

void ray_values(std::vector<double>* v, const Ray& r) {
  push3(v, r.o);
  push3(v, r.d);
  v->push_back(r.min_t);
  v->push_back(r.max_t);
}

// ---------------------------------------------------------------------------
// Part 1: generate_ray (deterministic).
std::vector<Check> probe_generate_ray() {
  std::vector<Check> out;
  const std::vector<Camera> cams = test_cameras();
  const double xs[] = {0.0, 0.1, 0.25, 0.5, 0.77, 1.0, -0.2, 1.3};
  for (size_t k = 0; k < cams.size(); ++k) {
    std::vector<double> v;
    for (double x : xs)
      for (double y : xs) ray_values(&v, generate_ray(cams[k], x, y));
    add(&out, "generate_ray: origin, direction, min_t, max_t on an 8x8 grid of (x, y), camera " + std::to_string(k),
        v);
  }
  return out;
}

// ---------------------------------------------------------------------------
// Part 1: camera_sample_ray.
std::vector<Check> probe_camera_sample_ray() {
  std::vector<Check> out;
  // jitter = false: the ray through the pixel centre, exactly.
  const std::vector<Camera> cams = test_cameras();
  for (size_t k = 0; k < cams.size(); ++k) {
    const Camera& c = cams[k];
    std::vector<double> v;
    const int px[] = {0, 1, c.width / 3, c.width / 2, c.width - 1};
    const int py[] = {0, 2, c.height / 2, c.height - 3, c.height - 1};
    Rng rng(7);
    for (int x : px)
      for (int y : py) ray_values(&v, camera_sample_ray(c, x, y, false, rng));
    add(&out, "camera_sample_ray: no jitter, rays through pixel centres, camera " + std::to_string(k), v);
  }
  // jitter = true: N = 4096 draws of pixel (2, 1) of film_camera(); the film
  // offset (u, v) should be uniform on [0, 1)^2. Standard errors: mean
  // sqrt(1/12/N) = 0.0045; variance ~sqrt(0.0056/N) = 0.0012 around 1/12;
  // covariance ~(1/12)/sqrt(N) = 0.0013 around 0 (one random number for
  // both axes gives 1/12); min and max ~1/N from 0 and 1. The difference of
  // two correct implementations has sqrt(2) those; the tolerances are 6 or
  // more of it, and far below what a wrong jitter shows (a mean off by 0.5,
  // a variance of 0, a covariance of 1/12).
  {
    const Camera c = film_camera();
    Rng rng(12345);
    const int N = 4096;
    double su = 0, sv = 0, suu = 0, svv = 0, suv = 0;
    double umin = 1e9, umax = -1e9, vmin = 1e9, vmax = -1e9;
    double omax = 0;
    for (int i = 0; i < N; ++i) {
      const Ray r = camera_sample_ray(c, 2, 1, true, rng);
      const double u = film_u(r), w = film_v(r);
      su += u, sv += w, suu += u * u, svv += w * w, suv += u * w;
      umin = std::min(umin, u), umax = std::max(umax, u);
      vmin = std::min(vmin, w), vmax = std::max(vmax, w);
      omax = std::max(omax, double(std::fabs(r.o.x) + std::fabs(r.o.y) + std::fabs(r.o.z)));
    }
    const double mu = su / N, mv = sv / N;
    add(&out, "camera_sample_ray: jittered film offset in the pixel, mean (u, v) of 4096 draws", {mu, mv}, 0.04, 0);
    add(&out, "camera_sample_ray: jittered film offset, variance of u and of v", {suu / N - mu * mu, svv / N - mv * mv},
        0.012, 0);
    add(&out, "camera_sample_ray: jittered film offset, covariance of u and v (independent axes)",
        {suv / N - mu * mv}, 0.012, 0);
    add(&out, "camera_sample_ray: jittered film offset, min u, max u, min v, max v", {umin, umax, vmin, vmax}, 0.01,
        0);
    add(&out, "camera_sample_ray: jittered rays start at the camera position", {omax}, 1e-6, 0);
  }
  // jitter = true on an oblique camera: the mean direction of 2048 draws of
  // one pixel (the pixel spans ~0.003 rad, so the mean's error is ~2e-5).
  {
    const Camera c = test_cameras()[1];
    Rng rng(99);
    const int N = 2048;
    double s[3] = {0, 0, 0};
    std::vector<double> v;
    for (int i = 0; i < N; ++i) {
      const Ray r = camera_sample_ray(c, 200, 37, true, rng);
      for (int a = 0; a < 3; ++a) s[a] += r.d[a];
      if (i == 0) v = {r.min_t, r.max_t};
    }
    for (int a = 0; a < 3; ++a) v.push_back(s[a] / N);
    add(&out, "camera_sample_ray: jittered, oblique camera 320x180, pixel (200, 37): min_t, max_t, mean direction",
        v, 3e-4, 0);
  }
  return out;
}

// ---------------------------------------------------------------------------
// Part 1: raytrace_pixel, with radiance functions supplied here.
std::vector<Check> probe_raytrace_pixel() {
  std::vector<Check> out;
  const Camera c = film_camera();
  const RadianceFn constant = [](const Ray&, Rng&) { return Color(0.25f, 0.5f, 2.0f); };
  // Radiance = where the ray crosses pixel (2, 1), in pixel units.
  const RadianceFn film = [](const Ray& r, Rng&) { return Color(float(film_u(r)), float(film_v(r)), 1.0f); };
  // Constant radiance: the average is that constant for any sampling.
  {
    std::vector<double> v;
    for (int n : {1, 3, 16, 64}) push3(&v, raytrace_pixel(c, 2, 1, n, 5, constant));
    add(&out, "raytrace_pixel: constant radiance (0.25, 0.5, 2), 1, 3, 16, 64 samples", v);
  }
  // One sample: the ray through the pixel centre (exact).
  {
    std::vector<double> v;
    push3(&v, raytrace_pixel(c, 2, 1, 1, 5, film));
    push3(&v, raytrace_pixel(c, 2, 1, 1, 77, film));
    const Camera b = test_cameras()[1];
    const RadianceFn dir = [](const Ray& r, Rng&) { return Color(r.d.x, r.d.y, r.d.z); };
    push3(&v, raytrace_pixel(b, 17, 150, 1, 3, dir));
    add(&out, "raytrace_pixel: one sample, film position / direction of the ray (pixel centre)", v);
  }
  // Calls to the radiance and distinct rays: num_samples calls, each sample
  // its own ray (its own random numbers).
  {
    std::vector<double> v;
    for (int n : {1, 3, 64}) {
      int calls = 0;
      std::set<std::tuple<float, float, float>> dirs;
      const RadianceFn rec = [&](const Ray& r, Rng&) {
        ++calls;
        dirs.insert({r.d.x, r.d.y, r.d.z});
        return Color(1.0f);
      };
      raytrace_pixel(c, 2, 1, n, 11, rec);
      v.push_back(calls);
      v.push_back(dirs.size() == size_t(n) ? 1 : 0);
    }
    add(&out, "raytrace_pixel: calls to the radiance and whether every sample's ray differs (1, 3, 64 samples)", v,
        0, 0);
  }
  // Film position averaged over seeds: uniform over the pixel, mean (0.5,
  // 0.5). 64 samples x 64 seeds = 4096 samples, standard error <= 0.0045
  // (less when stratified); 3 samples x 1500 seeds: 0.0043. Tolerance 0.04,
  // 6 standard errors of the difference of two correct implementations.
  {
    std::vector<double> v;
    for (int n : {3, 64}) {
      const int seeds = n == 3 ? 1500 : 64;
      double su = 0, sv = 0;
      for (int s = 0; s < seeds; ++s) {
        const Color L = raytrace_pixel(c, 2, 1, n, uint64_t(1000 + s), film);
        su += L.x, sv += L.y;
      }
      v.push_back(su / seeds);
      v.push_back(sv / seeds);
    }
    add(&out, "raytrace_pixel: mean film position of the samples over many seeds (3 and 64 samples)", v, 0.04, 0);
  }
  // The blue channel of `film` is 1 for every sample: the average is exactly 1.
  {
    std::vector<double> v;
    for (int n : {2, 3, 9, 64}) v.push_back(raytrace_pixel(c, 2, 1, n, 4, film).z);
    add(&out, "raytrace_pixel: average of a channel that is 1 for every sample (2, 3, 9, 64 samples)", v);
  }
  // A radiance that uses its own random numbers: mean 0.5 over 64 x 64
  // samples (standard error 0.0045; tolerance 0.04), and different seeds
  // differ.
  {
    const RadianceFn noise = [](const Ray&, Rng& rng) { return Color(rng.uniform()); };
    double s = 0;
    for (int k = 0; k < 64; ++k) s += raytrace_pixel(c, 1, 0, 64, uint64_t(300 + k), noise).x;
    const double a = raytrace_pixel(c, 2, 1, 16, 1, film).x, b = raytrace_pixel(c, 2, 1, 16, 2, film).x;
    const double e = raytrace_pixel(c, 2, 1, 16, 1, film).x;
    add(&out, "raytrace_pixel: mean of a radiance drawn from the sample's rng", {s / 64}, 0.04, 0);
    add(&out, "raytrace_pixel: seeds 1 and 2 differ, the same seed repeats", {a != b ? 1.0 : 0.0, a == e ? 1.0 : 0.0},
        0, 0);
  }
  return out;
}

// ---------------------------------------------------------------------------
// Part 1: intersect_triangle (deterministic).
Triangle tri(const Vec3& a, const Vec3& b, const Vec3& c, int material) {
  Triangle t;
  t.p1 = a, t.p2 = b, t.p3 = c;
  const Vec3 n = normalize(cross(b - a, c - a));
  // Distinct vertex normals, so that the interpolation weights show.
  t.n1 = normalize(n + Vec3(0.4f, 0, 0));
  t.n2 = normalize(n + Vec3(0, 0.4f, 0));
  t.n3 = normalize(n + Vec3(0, 0, 0.4f));
  t.material = material;
  return t;
}

void hit_values(std::vector<double>* v, bool hit, const Ray& r, const Hit& h) {
  v->push_back(hit ? 1 : 0);
  v->push_back(std::isfinite(r.max_t) ? r.max_t : -1.0);
  if (hit) {
    v->push_back(h.t);
    push3(v, h.n);
    v->push_back(h.material);
  } else {
    for (int k = 0; k < 5; ++k) v->push_back(0);
  }
}

std::vector<Check> probe_intersect_triangle() {
  std::vector<Check> out;
  std::vector<Triangle> tris = {
      tri(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 3),
      tri(Vec3(-1, -0.5f, -2), Vec3(1.5f, -0.2f, -2.5f), Vec3(0.1f, 1.3f, -1.7f), 1),
      tri(Vec3(0.3f, 0.2f, 0.7f), Vec3(-0.4f, 0.9f, -0.3f), Vec3(0.8f, -0.6f, 0.1f), 2),
  };
  // Rays: fixed ones (edges, vertices, parallel, behind, beyond max_t) and a
  // seeded set aimed around each triangle.
  std::vector<Ray> rays;
  rays.push_back(Ray(Vec3(0.25f, 0.25f, 1), Vec3(0, 0, -1)));          // inside tri 0
  rays.push_back(Ray(Vec3(0.5f, 0.5f, 1), Vec3(0, 0, -1)));            // on the hypotenuse
  rays.push_back(Ray(Vec3(0.5f, 0, 1), Vec3(0, 0, -1)));               // on an edge
  rays.push_back(Ray(Vec3(0, 0, 1), Vec3(0, 0, -1)));                  // on a vertex
  rays.push_back(Ray(Vec3(0.7f, 0.7f, 1), Vec3(0, 0, -1)));            // in the parallelogram, outside
  rays.push_back(Ray(Vec3(0.9f, 0.9f, -1), Vec3(0, 0, 1)));            // same, from behind
  rays.push_back(Ray(Vec3(0.25f, 0.25f, -1), Vec3(0, 0, 1)));          // from behind (back face)
  rays.push_back(Ray(Vec3(0.2f, 0.2f, 1), Vec3(1, 0, 0)));             // parallel
  rays.push_back(Ray(Vec3(0.2f, 0.1f, 1), Vec3(0, 0, 1)));             // away from it
  rays.push_back(Ray(Vec3(0.2f, 0.1f, 1), Vec3(0, 0, -1), 0.0f, 0.5f));  // beyond max_t
  rays.push_back(Ray(Vec3(0.2f, 0.1f, 1), Vec3(0, 0, -1), 1.5f, 3.0f));  // before min_t
  rays.push_back(Ray(Vec3(0.2f, 0.1f, 1), Vec3(0, 0, -1), 0.0f, 1.0f));  // exactly at max_t
  rays.push_back(Ray(Vec3(0.2f, 0.1f, 1), Vec3(0, 0, -1), 1.0f, 2.0f));  // exactly at min_t
  rays.push_back(Ray(Vec3(0.1f, 0.3f, 0), Vec3(0.3f, 0.2f, -1)));      // origin on it, min_t 1e-4
  rays.push_back(Ray(Vec3(0.1f, 0.3f, 0), Vec3(0.3f, 0.2f, -1), 0.0f));  // origin on it, min_t 0
  rays.push_back(Ray(Vec3(0.3f, 0.1f, 2), Vec3(0.1f, 0.05f, -2)));       // not unit direction
  const size_t fixed = rays.size();
  for (size_t k = 0; k < tris.size(); ++k) {
    // 90 seeded rays aimed around triangle k (barycentrics in [-0.1, 1.1]).
    rays.resize(fixed);
    Rng rng(2024 + k);
    const auto u = [&] { return rng.uniform() * 2.0f - 1.0f; };
    const Triangle& t = tris[k];
    for (int i = 0; i < 90; ++i) {
      const Vec3 o(3 * u(), 3 * u(), 3 * u());
      const float b1 = 0.6f * u() + 0.5f, b2 = 0.6f * u() + 0.5f;
      const Vec3 target = t.p1 + (t.p2 - t.p1) * b1 + (t.p3 - t.p1) * b2;
      Ray r(o, normalize(target - o));
      if (i % 5 == 0) r.max_t = norm(target - o) * (0.5f + rng.uniform());  // some end short, some beyond
      if (i % 7 == 0) r.min_t = norm(target - o) * rng.uniform() * 1.5f;
      rays.push_back(r);
    }
    std::vector<double> v, nohit;
    for (const Ray& r0 : rays) {
      Ray r = r0;
      Hit h;
      const bool hit = intersect_triangle(tris[k], r, &h);
      hit_values(&v, hit, r, h);
      Ray r2 = r0;  // with a null hit record
      const bool hit2 = intersect_triangle(tris[k], r2, nullptr);
      nohit.push_back(hit2 ? 1 : 0);
      nohit.push_back(std::isfinite(r2.max_t) ? r2.max_t : -1.0);
    }
    add(&out, "intersect_triangle: hit, max_t after, t, normal, material of " + std::to_string(rays.size()) +
                  " rays, triangle " + std::to_string(k),
        v);
    add(&out, "intersect_triangle: hit and max_t after with a null Hit, triangle " + std::to_string(k), nohit);
  }
  // A degenerate (zero-area) triangle is never hit.
  {
    const Triangle d = tri(Vec3(0, 0, 0), Vec3(1, 1, 0), Vec3(2, 2, 0), 0);
    std::vector<double> v;
    for (size_t i = 0; i < 16; ++i) {
      Ray r = rays[i];
      Hit h;
      v.push_back(intersect_triangle(d, r, &h) ? 1 : 0);
    }
    add(&out, "intersect_triangle: a zero-area triangle", v);
  }
  return out;
}

// ---------------------------------------------------------------------------
// Part 1: intersect_sphere (deterministic).
std::vector<Check> probe_intersect_sphere() {
  std::vector<Check> out;
  const std::vector<Sphere> spheres = {Sphere{Vec3(0, 0, 0), 1.0f, 4}, Sphere{Vec3(1.5f, -0.7f, -3), 0.3f, 2},
                                       Sphere{Vec3(-2, 1, 0.5f), 2.5f, 1}};
  std::vector<Check> dummy;
  for (size_t k = 0; k < spheres.size(); ++k) {
    const Sphere& s = spheres[k];
    const float R = s.radius;
    std::vector<Ray> rays;
    const Vec3 c = s.center;
    rays.push_back(Ray(c + Vec3(0, 0, 3 * R), Vec3(0, 0, -1)));                     // through the centre
    rays.push_back(Ray(c + Vec3(0.5f * R, 0.3f * R, 3 * R), Vec3(0, 0, -1)));       // off centre
    rays.push_back(Ray(c + Vec3(0.999f * R, 0, 3 * R), Vec3(0, 0, -1)));            // grazing, inside
    rays.push_back(Ray(c + Vec3(1.01f * R, 0, 3 * R), Vec3(0, 0, -1)));             // grazing, outside
    rays.push_back(Ray(c + Vec3(0.1f * R, -0.2f * R, 0.3f * R), Vec3(0.6f, 0, 0.8f)));  // inside: far side
    rays.push_back(Ray(c, normalize(Vec3(-1, 2, 0.5f))));                           // from the centre
    rays.push_back(Ray(c + Vec3(0, 0, 3 * R), Vec3(0, 0, 1)));                      // away from it
    rays.push_back(Ray(c + Vec3(0, 0, 3 * R), Vec3(0, 0, -1), 0.0f, 1.5f * R));     // short of it
    rays.push_back(Ray(c + Vec3(0, 0, 3 * R), Vec3(0, 0, -1), 2.5f * R, 10 * R));   // min_t past the near root
    rays.push_back(Ray(c + Vec3(0, 0, 3 * R), Vec3(0, 0, -1), 4.5f * R, 10 * R));   // min_t past both roots
    rays.push_back(Ray(c + Vec3(0, 0, 3 * R), Vec3(0, 0, -1), 0.0f, 3.0f * R));     // between the roots
    rays.push_back(Ray(c + Vec3(0, 0, 3 * R), Vec3(0.3f, -0.1f, -2.0f)));           // not unit direction
    rays.push_back(Ray(c + Vec3(0, R, 0), Vec3(0, 1, 0)));                          // on the surface, leaving
    rays.push_back(Ray(c + Vec3(0, R, 0), Vec3(0, -1, 0)));                         // on the surface, entering
    Rng rng(31 + k);
    const auto u = [&] { return rng.uniform() * 2.0f - 1.0f; };
    for (int i = 0; i < 80; ++i) {
      const Vec3 o = c + Vec3(u(), u(), u()) * (i % 4 == 0 ? 0.8f * R : 4 * R);
      const Vec3 target = c + Vec3(u(), u(), u()) * (1.3f * R);
      Ray r(o, normalize(target - o));
      if (i % 6 == 1) r.max_t = 2 * R * rng.uniform() + 0.5f * R;
      if (i % 9 == 2) r.min_t = 2 * R * rng.uniform();
      rays.push_back(r);
    }
    std::vector<double> v, nohit;
    for (const Ray& r0 : rays) {
      Ray r = r0;
      Hit h;
      const bool hit = intersect_sphere(s, r, &h);
      hit_values(&v, hit, r, h);
      Ray r2 = r0;
      const bool hit2 = intersect_sphere(s, r2, nullptr);
      nohit.push_back(hit2 ? 1 : 0);
      nohit.push_back(std::isfinite(r2.max_t) ? r2.max_t : -1.0);
    }
    add(&out, "intersect_sphere: hit, max_t after, t, normal, material of " + std::to_string(rays.size()) +
                  " rays, sphere " + std::to_string(k),
        v);
    add(&out, "intersect_sphere: hit and max_t after with a null Hit, sphere " + std::to_string(k), nohit);
  }
  return out;
}

// ---------------------------------------------------------------------------
// Part 2: slab_test (deterministic).
std::vector<Check> probe_slab_test() {
  std::vector<Check> out;
  struct Box {
    Vec3 lo, hi;
  };
  const std::vector<Box> boxes = {
      {Vec3(-1, -1, -1), Vec3(1, 1, 1)},
      {Vec3(0.5f, -0.25f, 2), Vec3(1.5f, 0.75f, 2.5f)},
      {Vec3(-2, 0, -3), Vec3(2, 0, 3)},            // flat in y
      {Vec3(0.25f, -0.75f, 1), Vec3(0.25f, 0.875f, 1)},  // flat in x and z: a segment
      {Vec3(-0.25f, -0.25f, -0.25f), Vec3(-0.25f, -0.25f, -0.25f)},  // a point
  };
  struct R {
    Vec3 o, d;
    float t0, t1;
  };
  std::vector<R> rays = {
      {Vec3(-5, 0.1f, 0.2f), Vec3(1, 0, 0), 0, kInf},          // parallel to x (inv_d inf in y, z)
      {Vec3(5, 0.1f, 0.2f), Vec3(-1, 0, 0), 0, kInf},          // negative x
      {Vec3(0.1f, 5, 0.2f), Vec3(0, -1, 0), 0, kInf},          // negative y
      {Vec3(0.1f, 0.2f, 5), Vec3(0, 0, -1), 0, kInf},          // negative z
      {Vec3(0.1f, 0.2f, 5), Vec3(0, 0, -1), 0, 3.5f},          // ends before the box
      {Vec3(0.1f, 0.2f, 5), Vec3(0, 0, -1), 4.5f, 20},         // starts inside the box
      {Vec3(0.1f, 0.2f, 5), Vec3(0, 0, -1), 6.5f, 20},         // starts past the box
      {Vec3(0.1f, 0.2f, 0.3f), Vec3(0.3f, -0.5f, 0.8f), 0, kInf},  // from inside
      {Vec3(-5, 3, 0.2f), Vec3(1, 0, 0), 0, kInf},             // parallel, outside the y slab
      {Vec3(-3, 2, -1), normalize(Vec3(1, -0.7f, 0.2f)), 0, kInf},
      {Vec3(3, -2, 4), normalize(Vec3(-0.9f, 0.6f, -1.1f)), 0.5f, 8},
      // Through the segment and the point at t = 1 exactly (binary
      // fractions): an interval of zero length that is still a hit. (No ray
      // lies in a box's plane along a zero direction component: 0 * inf.)
      {Vec3(-0.75f, 0.125f, 0), Vec3(1, 0, 1), 0, kInf},
      {Vec3(0.75f, 0.75f, 0.75f), Vec3(-1, -1, -1), 0, kInf},
      {Vec3(0.75f, 0.75f, 0.75f), Vec3(-1, -1, -1), 0, 1},     // ends there
      {Vec3(0.75f, 0.75f, 0.75f), Vec3(-1, -1, -1), 1, 3},     // starts there
  };
  Rng rng(555);
  const auto u = [&] { return rng.uniform() * 2.0f - 1.0f; };
  for (int i = 0; i < 120; ++i) {
    const Vec3 o(4 * u(), 4 * u(), 4 * u());
    Vec3 target(1.5f * u(), 1.5f * u(), 1.5f * u());
    if (i % 8 == 3) target.y = 0.0f;  // aimed at the flat box
    Vec3 d = normalize(target - o);
    if (i % 10 == 7) d = -d;  // pointing away
    float t0 = 0, t1 = kInf;
    if (i % 4 == 1) t1 = 0.5f + 6 * rng.uniform();
    if (i % 5 == 2) t0 = 4 * rng.uniform();
    rays.push_back({o, d, t0, t1});
  }
  const size_t shared = rays.size();
  for (size_t k = 0; k < boxes.size(); ++k) {
    // 50 rays aimed at box k (a point of the box grown by 0.3 each side).
    rays.resize(shared);
    Rng rk(900 + k);
    for (int i = 0; i < 50; ++i) {
      const auto w = [&] { return rk.uniform() * 1.6f - 0.3f; };
      const Vec3 e = boxes[k].hi - boxes[k].lo;
      const Vec3 target(boxes[k].lo.x + e.x * w(), boxes[k].lo.y + e.y * w(), boxes[k].lo.z + e.z * w());
      const Vec3 jitter(0.3f * (rk.uniform() * 2 - 1), 0.3f * (rk.uniform() * 2 - 1), 0.3f * (rk.uniform() * 2 - 1));
      const Vec3 o(4 * (rk.uniform() * 2 - 1), 4 * (rk.uniform() * 2 - 1), 4 * (rk.uniform() * 2 - 1));
      const Vec3 d = normalize(target + (i % 2 ? jitter : Vec3(0.0f)) - o);
      float t0 = 0, t1 = kInf;
      if (i % 4 == 1) t1 = 0.5f + 6 * rk.uniform();
      if (i % 5 == 2) t0 = 4 * rk.uniform();
      rays.push_back({o, d, t0, t1});
    }
    std::vector<double> v;
    for (const R& r : rays) {
      const Vec3 inv(1.0f / r.d.x, 1.0f / r.d.y, 1.0f / r.d.z);
      float te = -12345.0f;
      const bool hit = slab_test(boxes[k].lo, boxes[k].hi, r.o, inv, r.t0, r.t1, &te);
      v.push_back(hit ? 1 : 0);
      v.push_back(hit ? te : 0.0);
    }
    add(&out, "slab_test: hit and t_enter of " + std::to_string(rays.size()) + " rays, box " + std::to_string(k), v);
  }
  return out;
}

// ---------------------------------------------------------------------------
// Part 2: the BVH. A soup of random triangles and spheres, large triangles
// that overlap many others, an axis-aligned floor and wall of small
// triangles (flat leaves), and degenerate triangles.
Scene bvh_scene() {
  Scene s;
  for (int m = 0; m < 4; ++m) s.materials.push_back(Material{});
  Rng rng(4242);
  const auto u = [&] { return rng.uniform() * 2.0f - 1.0f; };
  for (int i = 0; i < 360; ++i) {
    const Vec3 c(u(), u(), u());
    const float size = i % 18 == 0 ? 0.7f : 0.03f + 0.2f * rng.uniform();
    s.triangles.push_back(tri(c + Vec3(u(), u(), u()) * size, c + Vec3(u(), u(), u()) * size,
                              c + Vec3(u(), u(), u()) * size, i % 4));
  }
  // Floor y = -1.4, 8 x 8 quads over [-1.2, 1.2]^2 (x, z).
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j) {
      const float x0 = -1.2f + 0.3f * i, z0 = -1.2f + 0.3f * j, x1 = x0 + 0.3f, z1 = z0 + 0.3f;
      s.triangles.push_back(tri(Vec3(x0, -1.4f, z0), Vec3(x0, -1.4f, z1), Vec3(x1, -1.4f, z0), (i + j) % 4));
      s.triangles.push_back(tri(Vec3(x1, -1.4f, z1), Vec3(x1, -1.4f, z0), Vec3(x0, -1.4f, z1), (i + j + 1) % 4));
    }
  // Wall x = 1.5, 4 x 4 quads over [-1, 1]^2 (y, z).
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      const float y0 = -1 + 0.5f * i, z0 = -1 + 0.5f * j, y1 = y0 + 0.5f, z1 = z0 + 0.5f;
      s.triangles.push_back(tri(Vec3(1.5f, y0, z0), Vec3(1.5f, y1, z0), Vec3(1.5f, y0, z1), 1));
      s.triangles.push_back(tri(Vec3(1.5f, y1, z1), Vec3(1.5f, y0, z1), Vec3(1.5f, y1, z0), 2));
    }
  // Degenerate triangles: collinear and a point.
  for (int i = 0; i < 6; ++i) {
    const Vec3 p(u(), u(), u());
    Triangle t;
    t.p1 = p, t.p2 = p + Vec3(0.1f, 0.05f, 0), t.p3 = p + Vec3(0.2f, 0.1f, 0);
    if (i % 2) t.p2 = t.p3 = p;
    t.n1 = t.n2 = t.n3 = Vec3(0, 1, 0);
    s.triangles.push_back(t);
  }
  for (int i = 0; i < 10; ++i) s.spheres.push_back(Sphere{Vec3(u(), u(), u()), 0.05f + 0.15f * rng.uniform(), i % 4});
  return s;
}

struct ProbeRay {
  Ray r;
  float shadow_max_t;  // the max_t of the occlusion query
};

// ~330 rays: from outside, from inside the soup, along the axes, with finite
// max_t, and from points on triangles (min_t = kRayEpsilon).
std::vector<ProbeRay> bvh_rays(const Scene& s) {
  std::vector<ProbeRay> rays;
  Rng rng(777);
  const auto u = [&] { return rng.uniform() * 2.0f - 1.0f; };
  const auto unit = [&] {
    for (;;) {
      const Vec3 v(u(), u(), u());
      const float n = norm(v);
      if (n > 0.1f && n <= 1) return v / n;
    }
  };
  for (int i = 0; i < 100; ++i) {  // from outside, towards the soup
    const Vec3 o = unit() * 4.0f;
    const Vec3 t(1.2f * u(), 1.4f * u(), 1.2f * u());
    rays.push_back({Ray(o, normalize(t - o)), 1.0f + 5 * rng.uniform()});
  }
  for (int i = 0; i < 70; ++i) {  // from inside
    const Vec3 o(0.9f * u(), 0.9f * u(), 0.9f * u());
    Ray r(o, unit());
    if (i % 2) r.max_t = 0.05f + 1.5f * rng.uniform();
    rays.push_back({r, 0.05f + 1.0f * rng.uniform()});
  }
  const Vec3 axes[6] = {Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(0, 0, 1), Vec3(0, 0, -1)};
  for (int i = 0; i < 36; ++i) {  // along the axes, from outside and inside
    const Vec3 d = axes[i % 6];
    Vec3 o(1.1f * u(), 1.1f * u(), 1.1f * u());
    if (i % 12 < 6) o = o - d * 3.0f;
    rays.push_back({Ray(o, d), 0.3f + 3 * rng.uniform()});
  }
  for (int i = 0; i < 24; ++i) {  // down onto the floor, some grazing
    const Vec3 o(1.2f * u(), -1.4f + (i % 3 == 0 ? 0.02f : 1.5f) * rng.uniform() + 0.001f, 1.2f * u());
    const Vec3 d = normalize(Vec3(u(), i % 3 == 0 ? -0.05f : -1.0f, u()));
    rays.push_back({Ray(o, d), 0.1f + 2 * rng.uniform()});
  }
  for (int i = 0; i < 80; ++i) {  // from a point on a triangle of the soup
    const size_t k = size_t(rng.next_u32() % 360);
    const Triangle& t = s.triangles[k];
    float b1 = rng.uniform(), b2 = rng.uniform();
    if (b1 + b2 > 1) b1 = 1 - b1, b2 = 1 - b2;
    const Vec3 p = t.p1 + (t.p2 - t.p1) * b1 + (t.p3 - t.p1) * b2;
    rays.push_back({Ray(p, unit()), 0.2f + 2 * rng.uniform()});
  }
  for (int i = 0; i < 20; ++i) {  // far outside, ending long before the scene
    const Vec3 o = unit() * 6.0f;
    const Vec3 t(0.5f * u(), 0.5f * u(), 0.5f * u());
    Ray r(o, normalize(t - o));
    r.max_t = 1.0f + rng.uniform();
    rays.push_back({r, r.max_t});
  }
  return rays;
}

// BVH::build: what the tree the student built shows through nodes() and
// leaf_primitives(): every primitive reachable from the root exactly once,
// every box holding its children's boxes and its primitives' boxes, the
// scene's box at the root. Nothing about the tree's shape.
void tree_invariants(std::vector<Check>* out, const Scene& s, const std::string& what) {
  const BVH bvh(s);
  const auto& nodes = bvh.nodes();
  const auto& ids = bvh.leaf_primitives();
  const size_t n = s.num_primitives();
  std::vector<int> seen(n, 0);
  double bad_ids = 0, box_violations = 0, leaves = 0, bad_links = 0;
  const auto prim_box = [&](uint32_t id) {
    return id < s.triangles.size() ? s.triangles[id].bounds() : s.spheres[id - s.triangles.size()].bounds();
  };
  const auto contains = [](const Vec3& lo, const Vec3& hi, const BBox& b) {
    return lo.x <= b.lo.x && lo.y <= b.lo.y && lo.z <= b.lo.z && hi.x >= b.hi.x && hi.y >= b.hi.y && hi.z >= b.hi.z;
  };
  std::vector<uint32_t> todo;
  if (!nodes.empty()) todo.push_back(0);
  size_t steps = 0;
  while (!todo.empty() && steps < 10 * (n + 10)) {
    ++steps;
    const BVHNode& node = nodes[todo.back()];
    todo.pop_back();
    if (node.is_leaf()) {
      ++leaves;
      for (uint32_t k = 0; k < node.count; ++k) {
        if (size_t(node.first) + k >= ids.size()) {
          ++bad_links;
          continue;
        }
        const uint32_t id = ids[node.first + k];
        if (id >= n) {
          ++bad_ids;
          continue;
        }
        ++seen[id];
        if (!contains(node.lo, node.hi, prim_box(id))) ++box_violations;
      }
    } else {
      for (uint32_t c = node.first; c < node.first + 2; ++c) {
        if (c >= nodes.size() || c == 0) {
          ++bad_links;
          continue;
        }
        if (!contains(node.lo, node.hi, BBox(nodes[c].lo, nodes[c].hi))) ++box_violations;
        todo.push_back(c);
      }
    }
  }
  double missing = 0, repeated = 0;
  for (int c : seen) missing += c == 0, repeated += c > 1 ? c - 1 : 0;
  add(out, "BVH::build (" + what + "): primitives missing from the leaves, repeated, ids out of range, bad links",
      {missing, repeated, bad_ids, bad_links + (todo.empty() ? 0 : 1)}, 0, 0);
  add(out, "BVH::build (" + what + "): boxes that do not hold a child's box or a primitive's box", {box_violations},
      0, 0);
  add(out, "BVH::build (" + what + "): has a leaf", {leaves > 0 ? 1.0 : 0.0}, 0, 0);
  const BBox b = bvh.bounds();
  std::vector<double> v;
  push3(&v, b.lo);
  push3(&v, b.hi);
  add(out, "BVH::build (" + what + "): bounds() of the scene", v, 0, 0);
}

std::vector<Check> probe_bvh_build() {
  std::vector<Check> out;
  const Scene s = bvh_scene();
  tree_invariants(&out, s, "soup of " + std::to_string(s.num_primitives()) + " primitives");
  Scene one;
  one.materials.push_back(Material{});
  one.triangles.push_back(tri(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 0));
  tree_invariants(&out, one, "one triangle");
  Scene sph;
  sph.materials.push_back(Material{});
  sph.spheres.push_back(Sphere{Vec3(0, 0, 0), 1.0f, 0});
  sph.spheres.push_back(Sphere{Vec3(3, 0.5f, 0), 0.5f, 0});
  sph.triangles.push_back(tri(Vec3(-1, 2, 0), Vec3(1, 2, 0), Vec3(0, 2, 1), 0));
  tree_invariants(&out, sph, "two spheres and a triangle");
  // Many primitives at the same centroid (a split that cannot separate them).
  Scene same;
  same.materials.push_back(Material{});
  for (int i = 0; i < 40; ++i) {
    const float a = 0.05f * float(i + 1);
    same.triangles.push_back(tri(Vec3(-a, -a, 0), Vec3(a, -a, 0), Vec3(0, 2 * a, 0), 0));
  }
  tree_invariants(&out, same, "40 triangles around one point");
  return out;
}

std::vector<Check> probe_bvh_intersect() {
  std::vector<Check> out;
  const Scene s = bvh_scene();
  const BVH bvh(s);
  const std::vector<ProbeRay> rays = bvh_rays(s);
  std::vector<double> hits, geom;
  for (const ProbeRay& pr : rays) {
    Ray r = pr.r;
    Hit h;
    const bool hit = bvh.intersect(r, &h);
    hits.push_back(hit ? 1 : 0);
    hits.push_back(hit ? h.primitive : -1);
    geom.push_back(hit ? h.t : -1.0);
    geom.push_back(std::isfinite(r.max_t) ? r.max_t : -1.0);
    if (hit) {
      push3(&geom, h.n);
      geom.push_back(h.material);
    } else {
      for (int k = 0; k < 4; ++k) geom.push_back(0);
    }
  }
  add(&out, "BVH::intersect: hit and primitive id of " + std::to_string(rays.size()) + " rays", hits, 0, 0);
  add(&out, "BVH::intersect: t, max_t after, normal, material of the same rays", geom);
  // A null Hit: the same answer.
  {
    std::vector<double> v;
    for (size_t i = 0; i < rays.size(); i += 3) {
      Ray r = rays[i].r;
      Hit h;
      v.push_back(bvh.intersect(r, &h) ? 1 : 0);
    }
    add(&out, "BVH::intersect: hit of every third ray again (same BVH, same answer)", v, 0, 0);
  }
  // The one-triangle scene and the sphere scene.
  {
    Scene sph;
    sph.materials.push_back(Material{});
    sph.spheres.push_back(Sphere{Vec3(0, 0, 0), 1.0f, 0});
    sph.spheres.push_back(Sphere{Vec3(3, 0.5f, 0), 0.5f, 0});
    sph.triangles.push_back(tri(Vec3(-1, 2, 0), Vec3(1, 2, 0), Vec3(0, 2, 1), 0));
    const BVH b2(sph);
    std::vector<double> v;
    for (size_t i = 0; i < 100; ++i) {
      Ray r = rays[i].r;
      Hit h;
      const bool hit = b2.intersect(r, &h);
      v.push_back(hit ? 1 : 0);
      v.push_back(hit ? h.primitive : -1);
      v.push_back(hit ? h.t : -1.0);
    }
    add(&out, "BVH::intersect: two spheres and a triangle, hit, primitive, t of 100 rays", v);
  }
  return out;
}

std::vector<Check> probe_bvh_occluded() {
  std::vector<Check> out;
  const Scene s = bvh_scene();
  const BVH bvh(s);
  const std::vector<ProbeRay> rays = bvh_rays(s);
  std::vector<double> v;
  for (const ProbeRay& pr : rays) {
    Ray r = pr.r;
    r.max_t = pr.shadow_max_t;
    v.push_back(bvh.occluded(r) ? 1 : 0);
  }
  add(&out, "BVH::occluded: " + std::to_string(rays.size()) + " rays with finite max_t", v, 0, 0);
  {
    std::vector<double> w;
    for (const ProbeRay& pr : rays) {
      Ray r = pr.r;
      r.max_t = kInf;
      w.push_back(bvh.occluded(r) ? 1 : 0);
    }
    add(&out, "BVH::occluded: the same rays with max_t infinite", w, 0, 0);
  }
  // The cost of a shadow query, as the counters show it (a BVH that does
  // not count shows 0, which passes): on average far fewer primitive tests
  // than the scene's primitives; and none for rays that end long before the
  // scene's box.
  {
    RayStats& st = thread_ray_stats();
    const uint64_t before = st.primitive_tests;
    for (const ProbeRay& pr : rays) {
      Ray r = pr.r;
      r.max_t = pr.shadow_max_t;
      bvh.occluded(r);
    }
    const double per_query = double(st.primitive_tests - before) / double(rays.size());
    double far_tested = 0;
    for (size_t i = rays.size() - 20; i < rays.size(); ++i) {
      const uint64_t b = st.primitive_tests;
      bvh.occluded(rays[i].r);
      far_tested += st.primitive_tests > b ? 1 : 0;
    }
    add(&out, "BVH::occluded: uses the tree (fewer than a tenth of the primitives tested per query on average)",
        {per_query < 0.1 * double(s.num_primitives()) ? 1.0 : 0.0}, 0, 0);
    add(&out, "BVH::occluded: rays ending before the scene's box that test a primitive", {far_tested}, 0, 0);
  }
  return out;
}

// ---------------------------------------------------------------------------
// Part 5: pixel_converged (deterministic). A sweep of tolerances, 3 % apart,
// over pixels of given mean, standard deviation and sample count: the answer
// flips somewhere in each sweep.
std::vector<Check> probe_pixel_converged() {
  std::vector<Check> out;
  struct P {
    double mean, sigma;
    int n;
  };
  const P pixels[] = {{1.0, 0.5, 32}, {0.2, 0.05, 64}, {3.0, 4.0, 16}, {0.5, 0.5, 2},
                      {1.0, 1.0, 3},  {0.01, 0.003, 128}, {2.0, 0.9, 256}, {0.7, 0.7, 1000}};
  for (const P& p : pixels) {
    const double s1 = p.mean * p.n;
    const double s2 = p.sigma * p.sigma * (p.n - 1) + s1 * s1 / p.n;
    std::vector<double> v;
    for (double T = 0.002; T < 5.0; T *= 1.03) v.push_back(pixel_converged(s1, s2, p.n, T) ? 1 : 0);
    char name[160];
    std::snprintf(name, sizeof name, "pixel_converged: tolerances 0.002 to 5 (x1.03), mean %g, sigma %g, n %d", p.mean,
                  p.sigma, p.n);
    add(&out, name, v, 0, 0);
  }
  {
    std::vector<double> v;
    // Black pixels (sum and sum of squares 0), pixels without variance, and
    // a raw grid of (s1, s2, n).
    for (int n : {2, 16, 32, 100}) {
      v.push_back(pixel_converged(0, 0, n, 0.05) ? 1 : 0);
      v.push_back(pixel_converged(0, 0, n, 0.0) ? 1 : 0);
      v.push_back(pixel_converged(0.5 * n, 0.25 * n, n, 0.05) ? 1 : 0);
      v.push_back(pixel_converged(0.5 * n, 0.25 * n, n, 0.0) ? 1 : 0);
      v.push_back(pixel_converged(2.0 * n, 4.0 * n, n, 0.01) ? 1 : 0);
    }
    for (double s1 : {0.5, 3.0, 10.0, 40.0})
      for (double s2 : {1.0, 8.0, 30.0, 200.0})
        for (int n : {2, 5, 32}) {
          if (s2 < 1.001 * s1 * s1 / n) continue;  // no samples have these sums (s2 >= s1^2 / n)
          for (double T : {0.01, 0.1, 0.5}) v.push_back(pixel_converged(s1, s2, n, T) ? 1 : 0);
        }
    add(&out, "pixel_converged: black pixels, constant pixels, a grid of (s1, s2, n, tolerance)", v, 0, 0);
  }
  return out;
}

// ---------------------------------------------------------------------------
// Part 5: raytrace_pixel_adaptive.
std::vector<Check> probe_raytrace_pixel_adaptive() {
  std::vector<Check> out;
  const Camera c = film_camera();
  AdaptiveOptions o32;
  o32.batch = 32;
  o32.tolerance = 0.05;
  // Constant radiance (variance 0): converges at the first check, exactly.
  {
    std::vector<double> v;
    int taken = -1;
    const RadianceFn half = [](const Ray&, Rng&) { return Color(0.5f); };
    const RadianceFn black = [](const Ray&, Rng&) { return Color(0.0f); };
    const RadianceFn tint = [](const Ray&, Rng&) { return Color(0.25f, 0.5f, 1.0f); };
    for (const RadianceFn* f : {&half, &black, &tint}) {
      for (int max : {1, 20, 256}) {
        const Color L = raytrace_pixel_adaptive(c, 2, 1, max, 9, *f, o32, &taken);
        push3(&v, L);
        v.push_back(taken);
      }
    }
    add(&out, "raytrace_pixel_adaptive: constant, black and tinted radiance, -s 1, 20, 256, batch 32: value, samples",
        v);
  }
  // Radiance 2u, u uniform, at tolerance 0.001: needs ~10^6 samples, so
  // every sample is taken (256, and 40 with a batch of 32, 300 with 64).
  // The value is a Monte-Carlo mean of uniform numbers, standard error
  // 0.577 / sqrt(256 * 10) = 0.011 over ten pixels: tolerance 0.08.
  {
    const RadianceFn noise = [](const Ray&, Rng& rng) { return Color(2.0f * rng.uniform()); };
    AdaptiveOptions tight = o32;
    tight.tolerance = 0.001;
    std::vector<double> counts;
    double mean = 0;
    for (int p = 0; p < 10; ++p) {
      int taken = -1;
      mean += raytrace_pixel_adaptive(c, p % 4, p / 4 % 2, 256, 100 + p, noise, tight, &taken).x / 10;
      counts.push_back(taken);
    }
    int taken = -1;
    raytrace_pixel_adaptive(c, 1, 1, 40, 5, noise, tight, &taken);
    counts.push_back(taken);
    AdaptiveOptions t64 = tight;
    t64.batch = 64;
    raytrace_pixel_adaptive(c, 1, 1, 300, 5, noise, t64, &taken);
    counts.push_back(taken);
    add(&out, "raytrace_pixel_adaptive: noise that never converges: samples taken", counts, 0, 0);
    add(&out, "raytrace_pixel_adaptive: noise that never converges: mean value over ten pixels", {mean}, 0.08, 0);
  }
  // Radiance 1 + 0.866 (u - 0.5): sigma^2 = 0.0625, so 1.96 sigma / sqrt(n)
  // <= 0.05 mu needs n >= ~96. With a batch of 64 the check at 64 fails
  // unless the sample variance comes out below 2/3 of sigma^2 (about 3
  // standard errors) and the one at 128 passes unless it comes out above
  // 4/3 of it (4 standard errors): every pixel takes 128, but a rare one.
  // Mean over 20 pixels, tolerance 8 (two pixels off by 64 would be 6.4).
  // The value: mean 1, standard error 0.25/sqrt(128 * 20) = 0.005;
  // tolerance 0.04.
  {
    const RadianceFn known = [](const Ray&, Rng& rng) { return Color(1.0f + 0.866f * (rng.uniform() - 0.5f)); };
    AdaptiveOptions o64;
    o64.batch = 64;
    o64.tolerance = 0.05;
    double mean_taken = 0, mean_value = 0;
    for (int p = 0; p < 20; ++p) {
      int taken = -1;
      mean_value += raytrace_pixel_adaptive(c, p % 4, p / 4 % 2, 256, 500 + p, known, o64, &taken).x / 20;
      mean_taken += taken / 20.0;
    }
    add(&out, "raytrace_pixel_adaptive: radiance of known variance (needs ~96 samples), batch 64: mean samples taken",
        {mean_taken}, 8, 0);
    add(&out, "raytrace_pixel_adaptive: radiance of known variance: mean value over 20 pixels", {mean_value}, 0.04, 0);
  }
  // The samples are spread over the pixel: the mean film position of
  // pixel (2, 1) over 16 seeds x 256 samples (standard error 0.0045;
  // tolerance 0.04).
  {
    const RadianceFn film = [](const Ray& r, Rng&) {
      return Color(float(film_u(r)), float(film_v(r)), 1.0f);
    };
    AdaptiveOptions tight = o32;
    tight.tolerance = 0.0001;
    double su = 0, sv = 0;
    for (int k = 0; k < 16; ++k) {
      int taken = -1;
      const Color L = raytrace_pixel_adaptive(c, 2, 1, 256, 40 + k, film, tight, &taken);
      su += L.x / 16, sv += L.y / 16;
    }
    add(&out, "raytrace_pixel_adaptive: mean film position of the samples (256 samples x 16 seeds)", {su, sv}, 0.04, 0);
  }
  return out;
}

}  // namespace

std::vector<FunctionProbe> probes_parts_1_2_5() {
  return {
      {"generate_ray", 1, probe_generate_ray},
      {"camera_sample_ray", 1, probe_camera_sample_ray},
      {"raytrace_pixel", 1, probe_raytrace_pixel},
      {"intersect_triangle", 1, probe_intersect_triangle},
      {"intersect_sphere", 1, probe_intersect_sphere},
      {"slab_test", 2, probe_slab_test},
      {"BVH::build", 2, probe_bvh_build},
      {"BVH::intersect", 2, probe_bvh_intersect},
      {"BVH::occluded", 2, probe_bvh_occluded},
      {"pixel_converged", 5, probe_pixel_converged},
      {"raytrace_pixel_adaptive", 5, probe_raytrace_pixel_adaptive},
  };
}

}  // namespace pt::probe
