// What `--part N` renders for one camera ray: the radiance function the
// pixel function calls once per sample, composed from the command line's
// options. The renderer (render_job.cpp) and the debugger's path inspector
// both take it from here, so a replayed sample is the rendered one.
#pragma once
#include "stages/part4_global_illumination/global_illumination.h"
#include "common/intersector.h"
#include "pathtracer/options.h"
#include "stages/part1_raytracing/pixel_sampling.h"
#include "common/scene.h"

namespace pt {

// The path options of -m, -o, --no-rr, --direct-only (at most one bounce)
// and --indirect-only.
PathOptions path_options(const RenderOptions& opts);

// Parts 1 and 2: normal shading. Part 3: emission plus one bounce of direct
// light (-l, -H). Parts 4 and 5: paths of up to -m bounces with Russian
// roulette (path_options). Every ray is traced against `geometry`; the
// function refers to `scene` and `geometry`, which must outlive it.
RadianceFn part_radiance(const Scene& scene, const Intersector& geometry, const RenderOptions& opts);

}  // namespace pt
