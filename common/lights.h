// Light sampling: from a shading point, a direction toward the light with
// its distance, the pdf of having chosen it (per unit solid angle; 1 for
// delta lights) and the radiance arriving along it. As in the course, the
// pdf is always positive and a sample that brings no light (the back of a
// one-sided area light) has zero radiance, so that the course's
// f * L * cos / pdf is 0 there, never 0 / 0.
#pragma once
#include <limits>

#include "common/path_recorder.h"
#include "common/samplers.h"
#include "common/scene.h"

namespace pt {

struct LightSample {
  Vec3 wi;                 // unit world direction from the point toward the light
  float distance = 0;      // to the sampled point on the light; infinite for lights at infinity
  float pdf = 1;           // solid-angle pdf; 1 for delta lights; always > 0
  Color radiance{0.0f};    // arriving along -wi at the point (before the BSDF and cosine); 0 = no light
};

constexpr float kInfinity = std::numeric_limits<float>::infinity();

// How an environment light is sampled when not uniformly (part 8's
// importance sampling; the render sets Light::sampler for --part 8 on).
class EnvironmentSampler {
 public:
  virtual ~EnvironmentSampler() = default;
  // A direction toward the map from two uniform numbers in [0, 1): its
  // solid-angle pdf and the map's radiance along it (distance infinite).
  virtual LightSample sample(float u1, float u2) const = 0;
  // The solid-angle density sample() draws the unit direction wi with.
  virtual float pdf(const Vec3& wi) const = 0;
};

// The given way of sampling an environment light: a direction uniform over
// the sphere (pdf 1 / (4 pi)) and the map's radiance along it.
inline LightSample sample_environment_uniform(const EnvironmentMap* map, float u1, float u2) {
  LightSample s;
  const float z = 1.0f - 2.0f * u1, r = std::sqrt(std::fmax(0.0f, 1.0f - z * z)), phi = 2.0f * kPi * u2;
  s.wi = Vec3(r * std::cos(phi), r * std::sin(phi), z);
  s.distance = kInfinity;
  s.pdf = 1.0f / (4.0f * kPi);
  s.radiance = map ? map->lookup(s.wi) : Color(0.0f);
  return s;
}

// Samples `light` as seen from `p` with uniform numbers u1, u2 in [0, 1).
// Area light: a uniform point on the rectangle, pdf dist^2 / (area |cos|),
// one-sided (no radiance behind it). Point light: intensity scaled by the
// COLLADA attenuation 1 / (c + l d + q d^2). Directional: radiance along
// its direction. Ambient: uniform over the upper (+Y) hemisphere.
// Environment: the light's sampler if it has one (part 8), else uniform
// over the sphere (pdf 1 / (4 pi)).
// The path inspector is told of each call (common/path_recorder.h).
inline LightSample sample_light(const Light& light, const Vec3& p, float u1, float u2);

namespace detail {
inline LightSample sample_light_at(const Light& light, const Vec3& p, float u1, float u2) {
  LightSample s;
  switch (light.type) {
    case LightType::Area: {
      const Vec3 q = light.position + light.dim_x * (u1 - 0.5f) + light.dim_y * (u2 - 0.5f);
      const Vec3 d = q - p;
      const float d2 = norm2(d);
      s.wi = -light.direction;  // (on the light itself: no light, any unit direction)
      if (!(d2 > 0)) return s;
      s.distance = std::sqrt(d2);
      s.wi = d / s.distance;
      const float cos_light = -dot(s.wi, light.direction);  // the light emits along `direction`
      if (cos_light <= 0) return s;                         // behind a one-sided light: no light
      const float area = norm(cross(light.dim_x, light.dim_y));
      s.pdf = d2 / (area * cos_light);
      s.radiance = light.radiance;
      return s;
    }
    case LightType::Point: {
      const Vec3 d = light.position - p;
      s.distance = norm(d);
      s.wi = Vec3(0, 1, 0);  // (at the light itself: no light, any unit direction)
      if (!(s.distance > 0)) return s;
      s.wi = d / s.distance;
      const float att = light.constant_attenuation + light.linear_attenuation * s.distance +
                        light.quadratic_attenuation * s.distance * s.distance;
      s.radiance = att > 0 ? light.radiance / att : Color(0.0f);
      return s;
    }
    case LightType::Directional:
      s.wi = -light.direction;
      s.distance = kInfinity;
      s.radiance = light.radiance;
      return s;
    case LightType::Environment:
      if (light.sampler) return light.sampler->sample(u1, u2);
      return sample_environment_uniform(light.environment.get(), u1, u2);
    case LightType::Ambient: {
      const Vec3 w = sample_uniform_hemisphere(u1, u2);  // about +Z; turn to +Y
      s.wi = Vec3(w.x, w.z, -w.y);
      s.distance = kInfinity;
      s.pdf = uniform_hemisphere_pdf();
      s.radiance = light.radiance;
      return s;
    }
  }
  return s;
}
}  // namespace detail

inline LightSample sample_light(const Light& light, const Vec3& p, float u1, float u2) {
  const LightSample s = detail::sample_light_at(light, p, u1, u2);
  record_light_sample(light, p, u1, u2, s);
  return s;
}

// Radiance that lights at infinity (ambient, environment) send along a ray
// that escapes the scene in direction d (pointing away from the scene).
inline Color escaped_radiance(const std::vector<Light>& lights, const Vec3& d) {
  Color L(0.0f);
  for (const Light& l : lights) {
    if (l.type == LightType::Ambient && d.y > 0) L += l.radiance;
    if (l.type == LightType::Environment && l.environment) L += l.environment->lookup(d);
  }
  return L;
}

}  // namespace pt
