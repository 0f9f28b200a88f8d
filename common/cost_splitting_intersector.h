// Splits the work of shadow queries from that of closest-hit queries.
// An intersector counts every primitive test and node visit into one total
// (RayStats::primitive_tests, node_visits); this wrapper notes how much of
// it each shadow query added, so that the two kinds of query can be judged
// apart (a BVH whose closest-hit traversal is good but whose occlusion
// query tests everything shows only here). One extra virtual call per
// query, none per primitive.
#pragma once
#include "common/intersector.h"
#include "common/stats.h"

namespace pt {

class CostSplittingIntersector final : public Intersector {
 public:
  explicit CostSplittingIntersector(const Intersector& inner) : inner_(inner) {}

  bool intersect(Ray& r, Hit* hit) const override { return inner_.intersect(r, hit); }

  bool occluded(const Ray& r) const override {
    RayStats& stats = thread_ray_stats();
    const uint64_t tests = stats.primitive_tests, visits = stats.node_visits;
    const bool blocked = inner_.occluded(r);
    stats.shadow_primitive_tests += stats.primitive_tests - tests;
    stats.shadow_node_visits += stats.node_visits - visits;
    return blocked;
  }

 private:
  const Intersector& inner_;
};

}  // namespace pt
