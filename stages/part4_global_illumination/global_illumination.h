// Part 4: global illumination: paths of many bounces, ended by Russian
// roulette.
#pragma once
#include "stages/part3_direct_lighting/direct_lighting.h"

namespace pt {

// Russian roulette: past the first indirect bounce a path continues with
// this probability, and what it brings back is divided by it.
constexpr float kContinueProbability = 0.7f;

struct PathOptions {
  int max_depth = 1;             // -m: camera rays start with this depth
  bool accumulate = true;        // -o 1: sum bounces 0..m; -o 0: only bounce m
  bool russian_roulette = true;  // --no-rr traces every path to max_depth
  bool skip_direct = false;      // --indirect-only: drop bounces 0 and 1
};

// Light leaving `hit` back along `r` after at least one bounce, for a ray
// of depth r.depth: the direct light at the hit (if bounces are
// accumulated, or if this is the last bounce), plus, while r.depth > 1, one
// sampled bounce (sample_f), continued with depth - 1 and weighted by
// f |cos| / pdf. At a delta BSDF (mirror, glass; part 6) there is no
// direct light; the emission (or sky) its bounce reaches is added instead,
// counted by the same rule (with -o 0, at the last vertex: a delta surface at
// depth 1 still traces its bounce, for that light only).
// The first bounce from a camera ray (depth == max_depth) is
// always traced; later ones survive Russian roulette with
// kContinueProbability and are divided by it. The course writes this
// recursively; a loop does the same and survives any -m (the reference's
// -m 1000000 --no-rr needs no stack per bounce).
Color at_least_one_bounce_radiance(const ShadingContext& ctx, const PathOptions& opts, const Ray& r,
                                   const Hit& hit, Rng& rng);

// What --part 4 renders for a camera ray.
Color est_radiance_global_illumination(const ShadingContext& ctx, const PathOptions& opts, const Ray& camera_ray,
                                       Rng& rng);

}  // namespace pt
