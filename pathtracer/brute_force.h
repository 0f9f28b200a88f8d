// The "no BVH" intersector of part 1: every ray tests every primitive.
#pragma once
#include "intersector.h"
#include "scene.h"

namespace pt {

class BruteForceIntersector final : public Intersector {
 public:
  explicit BruteForceIntersector(const Scene& scene) : scene_(scene) {}
  bool intersect(Ray& r, Hit* hit) const override;
  bool occluded(const Ray& r) const override;

 private:
  const Scene& scene_;
};

}  // namespace pt
