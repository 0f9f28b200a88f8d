#include "pathtracer/radiance.h"

#include <algorithm>

#include "stages/part3_direct_lighting/direct_lighting.h"
#include "stages/part1_raytracing/shading.h"

namespace pt {

PathOptions path_options(const RenderOptions& opts) {
  PathOptions path;
  path.max_depth = opts.direct_only ? std::min(opts.max_depth, 1) : opts.max_depth;
  path.accumulate = opts.accumulate_bounces;
  path.russian_roulette = opts.russian_roulette;
  path.skip_direct = opts.indirect_only;
  return path;
}

RadianceFn part_radiance(const Scene& scene, const Intersector& geometry, const RenderOptions& opts) {
  if (opts.part <= 2) return [&geometry](const Ray& r, Rng&) { return normal_shading(geometry, r); };
  ShadingContext ctx{scene, geometry};
  ctx.light_samples = opts.light_samples;
  ctx.hemisphere = opts.hemisphere_sampling;
  ctx.course_area_pdf = opts.course_area_pdf;
  if (opts.part == 3) return [ctx](const Ray& r, Rng& rng) { return direct_illumination(ctx, r, rng); };
  const PathOptions path = path_options(opts);
  return [ctx, path](const Ray& r, Rng& rng) { return est_radiance_global_illumination(ctx, path, r, rng); };
}

}  // namespace pt
