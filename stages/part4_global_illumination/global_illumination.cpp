#include "stages/part4_global_illumination/global_illumination.h"

#include <cmath>

#include "common/bsdf.h"
#include "common/frame.h"
#include "common/lights.h"
#include "common/path_recorder.h"
#include "common/todo.h"

namespace pt {

Color at_least_one_bounce_radiance(const ShadingContext& ctx, const PathOptions& opts, const Ray& r,
                                   const Hit& hit, Rng& rng) {
  // BEGIN SOLUTION
  // STUB: PT_TODO(4, "direct light only (one bounce)");
  // STUB: unused(opts);
  // STUB: return one_bounce_radiance(ctx, r, hit, rng);
  // One path, bounce by bounce, in a loop rather than by recursion: -m sets
  // the path length, and -m 1000000 --no-rr must not exhaust the stack.
  // `weight` is the product of f cos / pdf (and 1 / survival probability)
  // of the bounces so far.
  Color L(0.0f), weight(1.0f);
  Ray ray = r;
  Hit at = hit;
  for (;;) {
    const bool first_bounce = ray.depth == opts.max_depth;
    const Material& m = ctx.scene.materials[size_t(at.material)];
    // The light a vertex adds by itself, its direct light, counts at every
    // vertex (-o 1) or at the last one, depth 1 (-o 0).
    const bool direct_counts = (opts.accumulate || ray.depth == 1) && !(opts.skip_direct && first_bounce);
    // A delta BSDF (mirror, glass; part 6) reflects light from one
    // direction, which light sampling never finds: its direct light is the
    // emission its bounce reaches, so that bounce is traced even at the
    // last vertex (at -m 1 a mirror shows the light it faces).
    const bool delta = bsdf_is_delta(m);
    if (direct_counts && !delta) L += weight * one_bounce_radiance(ctx, ray, at, rng);
    if (ray.depth <= 1 && !(delta && direct_counts)) break;

    // The first indirect bounce is always traced; later ones play roulette.
    float survive = 1.0f;
    if (!first_bounce && ray.depth > 1 && opts.russian_roulette) {
      if (rng.uniform() >= kContinueProbability) break;
      survive = kContinueProbability;
    }
    const Frame frame = Frame::from_normal(at.n);
    const Vec3 wo = frame.to_local(-ray.d);
    Vec3 wi;
    float pdf = 0;
    const Color f = bsdf_sample_f(m, wo, rng.uniform(), rng.uniform(), &wi, &pdf);
    if (!(pdf > 0) || (f.x == 0 && f.y == 0 && f.z == 0)) break;
    Ray bounce(ray.at(at.t), frame.to_world(wi), kRayEpsilon, kInfinity, ray.depth - 1);
    const bool count_emission = delta && direct_counts;
    Hit next;
    if (!ctx.geometry.intersect(bounce, &next)) {  // the sky was counted by light sampling, unless at a delta
      if (count_emission)
        L += weight * f * (std::fabs(wi.z) / (pdf * survive)) * escaped_radiance(ctx.scene.lights, bounce.d);
      break;
    }
    // |cos theta|: a refracted wi lies below the surface.
    weight *= f * (std::fabs(wi.z) / (pdf * survive));
    if (count_emission) L += weight * zero_bounce_radiance(ctx, bounce, next);
    if (ray.depth <= 1) break;  // a delta vertex at the last depth: its direct light only
    ray = bounce;
    at = next;
  }
  return L;
  // END SOLUTION
}

Color est_radiance_global_illumination(const ShadingContext& ctx, const PathOptions& opts, const Ray& camera_ray,
                                       Rng& rng) {
  Ray r = camera_ray;
  r.depth = opts.max_depth;
  const bool count_zero = (opts.accumulate || opts.max_depth == 0) && !opts.skip_direct;
  Hit hit;
  // record_zero_bounce passes its value through to the path inspector
  // (common/path_recorder.h).
  if (!ctx.geometry.intersect(r, &hit))
    return record_zero_bounce(count_zero ? escaped_radiance(ctx.scene.lights, r.d) : Color(0.0f));
  Color L = record_zero_bounce(count_zero ? zero_bounce_radiance(ctx, r, hit) : Color(0.0f));
  if (opts.max_depth > 0) L += at_least_one_bounce_radiance(ctx, opts, r, hit, rng);
  return L;
}

}  // namespace pt
