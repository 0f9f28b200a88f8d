#include "stages/part3_direct_lighting/direct_lighting.h"

#include <algorithm>

#include "common/bsdf.h"
#include "common/frame.h"
#include "common/lights.h"
#include "common/path_recorder.h"
#include "common/todo.h"

namespace pt {

Color zero_bounce_radiance(const ShadingContext& ctx, const Ray& r, const Hit& hit) {
  (void)r;
  // BEGIN SOLUTION
  // STUB: PT_TODO(3, "lights give no light of their own: they look black");
  // STUB: unused(ctx, hit);
  // STUB: return Color(0.0f);
  return emission(ctx.scene.materials[size_t(hit.material)]);
  // END SOLUTION
}

// Rays are float: start each probe ray at min_t = kRayEpsilon (its
// default), not at the course's EPS_D = 1e-11, which is no offset in float.
Color estimate_direct_lighting_hemisphere(const ShadingContext& ctx, const Ray& r, const Hit& hit, Rng& rng) {
  // BEGIN SOLUTION
  // STUB: PT_TODO(3, "no direct light with -H: black");
  // STUB: unused(ctx, r, hit, rng);
  // STUB: return Color(0.0f);
  const Frame frame = Frame::from_normal(hit.n);
  const Vec3 p = r.at(hit.t);
  const Vec3 wo = frame.to_local(-r.d);
  const Material& m = ctx.scene.materials[size_t(hit.material)];
  const int n = std::max<int>(1, int(ctx.scene.lights.size()) * ctx.light_samples);
  Color sum(0.0f);
  for (int i = 0; i < n; ++i) {
    const Vec3 wi = sample_uniform_hemisphere(rng.uniform(), rng.uniform());
    const Vec3 w = frame.to_world(wi);
    Ray probe(p, w, kRayEpsilon, kInfinity);
    Hit h;
    const Color Li = ctx.geometry.intersect(probe, &h) ? zero_bounce_radiance(ctx, probe, h)
                                                       : escaped_radiance(ctx.scene.lights, w);
    sum += bsdf_f(m, wo, wi) * Li * (wi.z / uniform_hemisphere_pdf());
  }
  return sum / float(n);
  // END SOLUTION
}

// Two conventions of this code base (README, "Conventions that differ from
// the course's code"): rays are float, so start shadow rays at
// min_t = kRayEpsilon (the course's EPS_D = 1e-11 is no offset in float:
// self-shadowing, an image about half as bright); and sample_light's pdf is
// always positive, with zero radiance for a sample that brings no light.
Color estimate_direct_lighting_importance(const ShadingContext& ctx, const Ray& r, const Hit& hit, Rng& rng) {
  // BEGIN SOLUTION
  // STUB: PT_TODO(3, "no direct light: black but for the lights");
  // STUB: unused(ctx, r, hit, rng);
  // STUB: return Color(0.0f);
  const Frame frame = Frame::from_normal(hit.n);
  const Vec3 p = r.at(hit.t);
  const Vec3 wo = frame.to_local(-r.d);
  const Material& m = ctx.scene.materials[size_t(hit.material)];
  Color total(0.0f);
  for (const Light& light : ctx.scene.lights) {
    const int n = light.is_delta() ? 1 : ctx.light_samples;
    Color sum(0.0f);
    for (int i = 0; i < n; ++i) {
      const LightSample ls = sample_light(light, p, rng.uniform(), rng.uniform());
      // No light along it (the back of a one-sided light): no shadow ray.
      if (is_black(ls.radiance)) continue;
      const Vec3 wi = frame.to_local(ls.wi);
      if (wi.z <= 0) continue;  // the light is below the surface
      const float max_t = std::isfinite(ls.distance) ? ls.distance - kRayEpsilon : kInfinity;
      if (!(max_t > kRayEpsilon)) continue;
      if (ctx.geometry.occluded(Ray(p, ls.wi, kRayEpsilon, max_t))) continue;
      float pdf = ls.pdf;
      if (ctx.course_area_pdf && light.type == LightType::Area) pdf /= ls.distance;
      sum += bsdf_f(m, wo, wi) * ls.radiance * (wi.z / pdf);
    }
    total += sum / float(n);
  }
  return total;
  // END SOLUTION
}

Color one_bounce_radiance(const ShadingContext& ctx, const Ray& r, const Hit& hit, Rng& rng) {
  if (recording_path()) {  // the path inspector watches the estimate (common/path_recorder.h)
    record_direct_begin(r, hit);
    return record_direct_end(ctx.hemisphere ? estimate_direct_lighting_hemisphere(ctx, r, hit, rng)
                                            : estimate_direct_lighting_importance(ctx, r, hit, rng));
  }
  return ctx.hemisphere ? estimate_direct_lighting_hemisphere(ctx, r, hit, rng)
                        : estimate_direct_lighting_importance(ctx, r, hit, rng);
}

Color direct_illumination(const ShadingContext& ctx, const Ray& ray, Rng& rng) {
  Ray r = ray;
  Hit hit;
  if (!ctx.geometry.intersect(r, &hit)) return record_zero_bounce(escaped_radiance(ctx.scene.lights, r.d));
  const Color zero = record_zero_bounce(zero_bounce_radiance(ctx, r, hit));
  return zero + one_bounce_radiance(ctx, r, hit, rng);
}

}  // namespace pt
