// The interface between shading and geometry: a closest-hit query and an
// early-exit occlusion query over the whole scene. Part 1 answers them by
// testing every primitive, part 2 through the BVH. One virtual call per ray,
// never per primitive.
#pragma once
#include "common/ray.h"

namespace pt {

class Intersector {
 public:
  virtual ~Intersector() = default;
  // Nearest hit with t in [r.min_t, r.max_t]; on a hit fills *hit and sets
  // r.max_t = hit->t. Counts one closest-hit query.
  virtual bool intersect(Ray& r, Hit* hit) const = 0;
  // Whether anything lies in [r.min_t, r.max_t]. Counts one shadow query.
  virtual bool occluded(const Ray& r) const = 0;
};

}  // namespace pt
