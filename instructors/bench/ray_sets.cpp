#include "instructors/bench/ray_sets.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "stages/part1_raytracing/camera_rays.h"
#include "common/math_constants.h"
#include "common/rng.h"

namespace pt::bench {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// Any two unit vectors completing `n` to a right-handed orthonormal basis.
void basis_about(const Vec3& n, Vec3* t, Vec3* b) {
  const Vec3 helper = std::fabs(n.x) > 0.9f ? Vec3(0, 1, 0) : Vec3(1, 0, 0);
  *t = normalize(cross(helper, n));
  *b = cross(n, *t);
}

// Cosine-weighted direction in the hemisphere about unit `n`.
Vec3 cosine_direction(const Vec3& n, Rng& rng) {
  const float u1 = rng.uniform(), u2 = rng.uniform();
  const float r = std::sqrt(u1), phi = 2.0f * kPi * u2;
  const float z = std::sqrt(std::max(0.0f, 1.0f - u1));
  Vec3 t, b;
  basis_about(n, &t, &b);
  return normalize(t * (r * std::cos(phi)) + b * (r * std::sin(phi)) + n * z);
}

// Unit geometric normal of the primitive hit at `p`, facing the side the ray
// `d` came from.
Vec3 facing_normal(const Scene& scene, const Hit& hit, const Vec3& p, const Vec3& d) {
  Vec3 n = hit.n;
  const size_t nt = scene.triangles.size();
  if (hit.primitive >= 0 && size_t(hit.primitive) < nt) {
    const Triangle& tri = scene.triangles[size_t(hit.primitive)];
    n = cross(tri.p2 - tri.p1, tri.p3 - tri.p1);
  } else if (hit.primitive >= 0 && size_t(hit.primitive) - nt < scene.spheres.size()) {
    n = p - scene.spheres[size_t(hit.primitive) - nt].center;
  }
  n = normalize(n);
  return dot(n, d) > 0 ? -n : n;
}

}  // namespace

RaySets make_ray_sets(const Scene& scene, const Intersector& isect, uint64_t num_primary, uint64_t seed) {
  if (scene.num_primitives() == 0) throw std::runtime_error(scene.source + ": the scene has no geometry");
  RaySets sets;
  const BBox bounds = scene.bounds();
  // An offset well above float rounding at the scene's scale and well below
  // its smallest features.
  sets.epsilon = std::max(1e-4f * norm(bounds.extent()), 1e-6f);
  const float eps = sets.epsilon;

  // Primary rays: ray i goes through a uniformly jittered point of pixel
  // floor((i + u) * W * H / N), so the N rays cover the image evenly, in
  // scanline order, whatever N is.
  const Camera& cam = scene.camera;
  const uint64_t pixels = uint64_t(cam.width) * uint64_t(cam.height);
  Rng prng(seed, 1);
  sets.primary.reserve(num_primary);
  for (uint64_t i = 0; i < num_primary; ++i) {
    const double s = (double(i) + prng.uniform_double()) * double(pixels) / double(num_primary);
    const uint64_t pixel = std::min(uint64_t(s), pixels - 1);
    const double x = double(pixel % uint64_t(cam.width)) + prng.uniform_double();
    const double y = double(pixel / uint64_t(cam.width)) + prng.uniform_double();
    const Ray r = generate_ray(cam, x / cam.width, y / cam.height);
    sets.primary.push_back(RayRecord::from(r.o, r.d, r.min_t, r.max_t));
  }

  // Secondary rays from the primary hits, in primary order.
  Rng drng(seed, 2), srng(seed, 3);
  for (const RayRecord& rec : sets.primary) {
    Ray r = rec.to_ray();
    Hit hit;
    if (!isect.intersect(r, &hit)) continue;
    const Vec3 p = r.at(hit.t);
    const Vec3 n = facing_normal(scene, hit, p, r.d);
    const Vec3 o = p + n * eps;

    sets.diffuse.push_back(RayRecord::from(o, cosine_direction(n, drng), 0.0f, kInf));

    if (scene.lights.empty()) continue;
    const size_t li = std::min(size_t(srng.uniform() * float(scene.lights.size())), scene.lights.size() - 1);
    const Light& light = scene.lights[li];
    const float u = srng.uniform(), v = srng.uniform();
    Vec3 d;
    float tmax = kInf;
    bool emitting_side = true;
    switch (light.type) {
      case LightType::Area:
      case LightType::Point: {
        const Vec3 q = light.type == LightType::Area
                           ? light.position + light.dim_x * (u - 0.5f) + light.dim_y * (v - 0.5f)
                           : light.position;
        const Vec3 to = q - o;
        const float dist = norm(to);
        if (!(dist > eps)) continue;
        d = to / dist;
        tmax = dist * (1.0f - 1e-4f);
        if (light.type == LightType::Area) emitting_side = dot(light.direction, d) < 0;
        break;
      }
      case LightType::Directional:
        d = normalize(-light.direction);
        tmax = 1e30f;
        break;
      case LightType::Environment:
      case LightType::Ambient:
        d = cosine_direction(n, srng);
        break;
    }
    if (dot(d, n) <= 0 || !emitting_side) continue;  // the renderer would not trace it
    sets.shadow.push_back(RayRecord::from(o, d, eps, tmax));
  }
  return sets;
}

}  // namespace pt::bench
