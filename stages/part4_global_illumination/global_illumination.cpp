#include "global_illumination.h"

#include "bsdf.h"
#include "frame.h"
#include "lights.h"
#include "todo.h"

namespace pt {

Color at_least_one_bounce_radiance(const ShadingContext& ctx, const PathOptions& opts, const Ray& r,
                                   const Hit& hit, Rng& rng) {
  // BEGIN SOLUTION
  // STUB: todo_once("Part 4: at_least_one_bounce_radiance (stages/part4_global_illumination/global_illumination.cpp)");
  // STUB: (void)opts;
  // STUB: return one_bounce_radiance(ctx, r, hit, rng);
  Color L(0.0f);
  const bool first_bounce = r.depth == opts.max_depth;
#ifdef PT_MUTANT_o0_accumulates
  if (!(opts.skip_direct && first_bounce))  // every bounce, even with -o 0
#else
  if ((opts.accumulate || r.depth == 1) && !(opts.skip_direct && first_bounce))
#endif
    L += one_bounce_radiance(ctx, r, hit, rng);
  if (r.depth <= 1) return L;

  // The first indirect bounce is always traced; later ones play roulette.
  float survive = 1.0f;
  if (!first_bounce && opts.russian_roulette) {
    if (rng.uniform() >= kContinueProbability) return L;
#ifdef PT_MUTANT_no_rr_division
    // Survivors are not divided by the continuation probability.
#else
    survive = kContinueProbability;
#endif
  }
  const Frame frame = Frame::from_normal(hit.n);
  const Vec3 wo = frame.to_local(-r.d);
  const Material& m = ctx.scene.materials[size_t(hit.material)];
  Vec3 wi;
  float pdf = 0;
  const Color f = bsdf_sample_f(m, wo, rng.uniform(), rng.uniform(), &wi, &pdf);
  if (!(pdf > 0) || (f.x == 0 && f.y == 0 && f.z == 0)) return L;
  Ray bounce(r.at(hit.t), frame.to_world(wi), kRayEpsilon, kInfinity, r.depth - 1);
  Hit next;
  if (!ctx.geometry.intersect(bounce, &next)) return L;  // the sky was counted by light sampling
  L += f * at_least_one_bounce_radiance(ctx, opts, bounce, next, rng) * (wi.z / (pdf * survive));
  return L;
  // END SOLUTION
}

Color est_radiance_global_illumination(const ShadingContext& ctx, const PathOptions& opts, const Ray& camera_ray,
                                       Rng& rng) {
  Ray r = camera_ray;
  r.depth = opts.max_depth;
  const bool count_zero = (opts.accumulate || opts.max_depth == 0) && !opts.skip_direct;
  Hit hit;
  if (!ctx.geometry.intersect(r, &hit)) return count_zero ? escaped_radiance(ctx.scene.lights, r.d) : Color(0.0f);
  Color L = count_zero ? zero_bounce_radiance(ctx, r, hit) : Color(0.0f);
  if (opts.max_depth > 0) L += at_least_one_bounce_radiance(ctx, opts, r, hit, rng);
  return L;
}

}  // namespace pt
