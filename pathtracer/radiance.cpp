#include "pathtracer/radiance.h"

#include <algorithm>

#include "stages/part3_direct_lighting/direct_lighting.h"
#include "stages/part1_raytracing/shading.h"
#include "stages/part6_mirror_glass/specular.h"
#include "stages/part7_microfacet/microfacet.h"
#include "stages/part8_environment_light/environment_sampling.h"

namespace pt {

PathOptions path_options(const RenderOptions& opts) {
  PathOptions path;
  path.max_depth = opts.direct_only ? std::min(opts.max_depth, 1) : opts.max_depth;
  path.accumulate = opts.accumulate_bounces;
  path.russian_roulette = opts.russian_roulette;
  path.skip_direct = opts.indirect_only;
  return path;
}

std::shared_ptr<const PartShading> part_shading(const Scene& scene, int part, bool bsdf_hemisphere) {
  auto s = std::make_shared<PartShading>();
  s->materials = scene.materials;
  for (Material& m : s->materials) {
    m.model = nullptr;  // the given default of its type
    switch (m.type) {
      case MaterialType::Mirror: m.model = part >= 6 ? &kMirrorModel : nullptr; break;
      case MaterialType::Refraction: m.model = part >= 6 ? &kRefractionModel : nullptr; break;
      case MaterialType::Glass: m.model = part >= 6 ? &kGlassModel : nullptr; break;
      case MaterialType::Microfacet:
        m.model = part < 7 ? nullptr : bsdf_hemisphere ? &kMicrofacetCosineModel : &kMicrofacetModel;
        break;
      default: break;
    }
  }
  s->lights = scene.lights;
  for (Light& l : s->lights) {
    l.sampler = nullptr;
    if (part >= 8 && l.type == LightType::Environment && l.environment)
      l.sampler = std::make_shared<const ImportanceEnvironmentSampler>(l.environment);
  }
  return s;
}

RadianceFn part_radiance(const Scene& scene, const Intersector& geometry, const RenderOptions& opts) {
  if (opts.part <= 2) return [&geometry](const Ray& r, Rng&) { return normal_shading(geometry, r); };
  // The lambdas below keep the shading data alive.
  const std::shared_ptr<const PartShading> shading = part_shading(scene, opts.part, opts.bsdf_hemisphere);
  ShadingContext ctx{ShadingScene(shading->materials, shading->lights), geometry};
  ctx.light_samples = opts.light_samples;
  ctx.hemisphere = opts.hemisphere_sampling;
  ctx.course_area_pdf = opts.course_area_pdf;
  if (opts.part == 3)
    return [ctx, shading](const Ray& r, Rng& rng) { return direct_illumination(ctx, r, rng); };
  const PathOptions path = path_options(opts);
  return [ctx, path, shading](const Ray& r, Rng& rng) {
    return est_radiance_global_illumination(ctx, path, r, rng);
  };
}

}  // namespace pt
