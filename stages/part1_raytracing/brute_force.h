// Testing every primitive of the scene in turn: the intersector of part 1
// (no acceleration structure yet), and what a BVH that is not written yet
// falls back on.
#pragma once
#include "common/intersector.h"
#include "common/scene.h"

namespace pt {

// The nearest hit of `r` among all the scene's primitives (triangles, then
// spheres, each with intersect_triangle / intersect_sphere); on a hit,
// hit->primitive is the triangle's index, or the number of triangles plus
// the sphere's index. Counts one primitive test per primitive.
bool intersect_every_primitive(const Scene& scene, Ray& r, Hit* hit);

// Whether some primitive blocks `r` within [r.min_t, r.max_t]; stops at the
// first that does. Counts one primitive test per primitive tried.
bool any_primitive_occludes(const Scene& scene, const Ray& r);

// The two functions above as an Intersector, counting each query.
class BruteForceIntersector final : public Intersector {
 public:
  explicit BruteForceIntersector(const Scene& scene) : scene_(scene) {}
  bool intersect(Ray& r, Hit* hit) const override;
  bool occluded(const Ray& r) const override;

 private:
  const Scene& scene_;
};

}  // namespace pt
