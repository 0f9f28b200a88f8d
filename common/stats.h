// Exact ray-query counters. Each render thread counts into its own copy
// (no shared atomics on the hot path); the render loop sums them at the end.
#pragma once
#include <cstdint>

namespace pt {

struct RayStats {
  uint64_t closest_queries = 0;  // closest-hit queries (camera and bounce rays)
  uint64_t shadow_queries = 0;   // occlusion queries (shadow rays)
  uint64_t primitive_tests = 0;  // ray-triangle and ray-sphere tests
  uint64_t node_visits = 0;      // BVH nodes visited
  // The part of the two totals above spent on shadow queries (the rest went
  // to closest-hit queries). Counted around each query by
  // CostSplittingIntersector, so the BVH itself only counts totals.
  uint64_t shadow_primitive_tests = 0;
  uint64_t shadow_node_visits = 0;

  uint64_t rays() const { return closest_queries + shadow_queries; }
  RayStats& operator+=(const RayStats& o) {
    closest_queries += o.closest_queries;
    shadow_queries += o.shadow_queries;
    primitive_tests += o.primitive_tests;
    node_visits += o.node_visits;
    shadow_primitive_tests += o.shadow_primitive_tests;
    shadow_node_visits += o.shadow_node_visits;
    return *this;
  }
};

// The calling thread's counters. Inline: every ray query counts, and a call
// into another file for each was a measurable share of a query that misses
// the scene at its first box.
inline RayStats& thread_ray_stats() {
  static thread_local RayStats stats;
  return stats;
}

}  // namespace pt
