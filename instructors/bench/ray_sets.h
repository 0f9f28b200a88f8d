// The benchmark's ray sets: deterministic functions of (scene, camera, seed,
// ray count), generated the way a path tracer produces its rays.
//
//   primary  camera rays through jittered points covering the whole image
//   diffuse  one per primary hit: a cosine-distributed bounce about the
//            geometric normal (turned toward the incoming ray)
//   shadow   one per primary hit: toward a uniformly chosen point on a
//            uniformly chosen light, when the renderer would trace it (the
//            light sample is above the surface and, for an area light, on
//            its emitting side)
#pragma once
#include <cstdint>
#include <vector>

#include "common/intersector.h"
#include "instructors/bench/ray_files.h"
#include "common/scene.h"

namespace pt::bench {

struct RaySets {
  std::vector<RayRecord> primary, diffuse, shadow;
  float epsilon = 0;  // surface offset used for diffuse and shadow origins
};

// `scene.camera` must already be configured (size, crop). `isect` finds the
// primary hits the secondary rays start from. Throws std::runtime_error on
// a scene it cannot make rays for (no triangles).
RaySets make_ray_sets(const Scene& scene, const Intersector& isect, uint64_t num_primary, uint64_t seed);

}  // namespace pt::bench
