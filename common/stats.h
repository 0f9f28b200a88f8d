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

  uint64_t rays() const { return closest_queries + shadow_queries; }
  RayStats& operator+=(const RayStats& o) {
    closest_queries += o.closest_queries;
    shadow_queries += o.shadow_queries;
    primitive_tests += o.primitive_tests;
    node_visits += o.node_visits;
    return *this;
  }
};

// The calling thread's counters.
RayStats& thread_ray_stats();

}  // namespace pt
