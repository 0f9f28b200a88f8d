// What `--part N` renders for one camera ray: the radiance function the
// pixel function calls once per sample, composed from the command line's
// options. The renderer (render_job.cpp) and the debugger's path inspector
// both take it from here, so a replayed sample is the rendered one.
#pragma once
#include <memory>
#include <vector>

#include "stages/part4_global_illumination/global_illumination.h"
#include "common/intersector.h"
#include "pathtracer/options.h"
#include "stages/part1_raytracing/pixel_sampling.h"
#include "common/scene.h"

namespace pt {

// The path options of -m, -o, --no-rr, --direct-only (at most one bounce)
// and --indirect-only.
PathOptions path_options(const RenderOptions& opts);

// The materials and lights a render of `part` shades with: the scene's, with
// each material's BSDF model (common/bsdf.h) that of the part that writes
// it when that part is rendered (part 6: mirror, refraction, glass; part 7:
// microfacet; before: the given stand-in, which reflects nothing) and, from
// part 8 on, each environment light importance-sampled (part 8's sampler;
// before: uniformly).
struct PartShading {
  std::vector<Material> materials;
  std::vector<Light> lights;
};
// `bsdf_hemisphere` (--bsdf-hemisphere): microfacet materials get part 7's
// cosine-sampled model (the write-up's baseline) instead.
std::shared_ptr<const PartShading> part_shading(const Scene& scene, int part, bool bsdf_hemisphere = false);

// Parts 1 and 2: normal shading. Part 3: emission plus one bounce of direct
// light (-l, -H). Parts 4 and 5: paths of up to -m bounces with Russian
// roulette (path_options); from part 6 on, with the BSDFs and samplers of
// part_shading. Every ray is traced against `geometry`; the
// function refers to `scene` and `geometry`, which must outlive it.
RadianceFn part_radiance(const Scene& scene, const Intersector& geometry, const RenderOptions& opts);

}  // namespace pt
