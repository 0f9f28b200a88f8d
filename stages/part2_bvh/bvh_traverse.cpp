// Part 2, task 3: closest-hit and occlusion queries through the BVH.
#include <algorithm>
#include <cmath>

#include "stages/part1_raytracing/brute_force.h"
#include "stages/part2_bvh/bvh.h"
#include "stages/part2_bvh/slab_test.h"
// BEGIN SOLUTION
#include <functional>

#include "stages/part2_bvh/bvh_wide.h"
// END SOLUTION
#include "stages/part1_raytracing/sphere.h"
#include "common/stats.h"
#include "common/todo.h"
#include "stages/part1_raytracing/triangle.h"

namespace pt {

namespace {

// BEGIN SOLUTION
// The reference traverses the 8-wide tree that BVH::build collapses from
// its binary SAH tree (bvh_wide.h says what each piece is and why it pays);
// the counters keep their definitions (bvh_wide.h).

// The lane of the nearest hit among `mask`; on a tie the last such lane, as
// testing the lanes one by one with r.max_t shortened at each hit would pick.
inline int nearest_lane(int mask, const float t[4]) {
  int best = __builtin_ctz(unsigned(mask));
  for (mask &= mask - 1; mask != 0; mask &= mask - 1) {
    const int lane = __builtin_ctz(unsigned(mask));
    if (t[lane] <= t[best]) best = lane;
  }
  return best;
}

inline int lowest_bit(int mask) { return __builtin_ctz(unsigned(mask)); }

// Asks for the cache lines of a hit triangle's normals and material, which
// the query reads once traversal ends: a new nearest hit is usually the
// final one, and on a large mesh its triangle is not in cache.
inline void prefetch_shading(const std::vector<Triangle>& triangles, uint32_t id) {
  if (id >= triangles.size()) return;  // a sphere lane
  const char* first = reinterpret_cast<const char*>(&triangles[id].n1);
  _mm_prefetch(first, _MM_HINT_T0);
  _mm_prefetch(reinterpret_cast<const char*>(&triangles[id].material), _MM_HINT_T0);
}

// Takes up the children of `n` in `mask` (at least one; entry distances in
// t): returns the one to visit next and pushes the others so that they pop
// in the order `before` gives (before(a, b): a child entered at a is
// visited before one entered at b). Insertion into the few just pushed.
template <typename Before>
inline WideEntry enter_children(const WideNode& n, int mask, const float* t, Before before, WideEntry* stack,
                                int& sp) {
  const int c = lowest_bit(mask);
  mask &= mask - 1;
  if (mask == 0) return {n.child[c], n.count[c], t[c]};  // one child: no stack at all
  WideEntry* const base = stack + sp;
  int top = sp;
  stack[top++] = {n.child[c], n.count[c], t[c]};
  for (; mask != 0; mask &= mask - 1) {
    const int k = lowest_bit(mask);
    const WideEntry e{n.child[k], n.count[k], t[k]};
    int j = top++;
    while (stack + j > base && before(stack[j - 1].t, e.t)) {
      stack[j] = stack[j - 1];
      --j;
    }
    stack[j] = e;
  }
  sp = top - 1;
  return stack[sp];
}

// The wide tree is at most as deep as the binary one (under 128 levels, see
// bvh_build.cpp), and a wide node pushes at most all its children but one.
constexpr int kStackSize = (kWideWidth - 1) * 128 + kWideWidth;

// END SOLUTION

}  // namespace

bool BVH::intersect(Ray& r, Hit* hit) const {
  RayStats& stats = thread_ray_stats();
  ++stats.closest_queries;
  if (nodes_.empty()) return false;
  // BEGIN SOLUTION
  // STUB: PT_TODO_AS(2, "BVH::intersect", "every ray tests every primitive");
  // STUB: return intersect_every_primitive(scene_, r, hit);
  const WideRay wr(r);
  if (!wr.finite) return false;  // as brute force: such a ray hits nothing
  const __m128 t_min = _mm_set1_ps(r.min_t);
  uint64_t tests = 0, visits = 0;
  uint32_t best_packet = 0;
  int best_lane = -1;  // lane of the nearest hit so far in wide_.packets[best_packet]
  bool best_is_sphere = false;
  float best_b1 = 0, best_b2 = 0;
  Hit sphere_hit;

  WideEntry stack[kStackSize];
  int sp = 0;
  WideEntry cur{0, wide_.root_count, r.min_t};
  for (;;) {
    ++visits;
    if (cur.count == 0) {
      // Interior: test the children's boxes; go on to the nearest hit
      // one and push the others, farthest first.
      const WideNode& n = wide_.nodes[cur.child];
      alignas(16) float t[kWideWidth];
      const int mask = wide_box_test(n, wr, t_min, _mm_set1_ps(r.max_t), t);
      if (mask != 0) {
        cur = enter_children(n, mask, t, std::less<float>(), stack, sp);
        continue;
      }
    } else {
      // Leaf: its packets, nearest hit kept.
      LeafLanes leaf(cur.count);
      uint32_t lanes;
      int lane_mask;
      for (uint32_t pi = cur.child; leaf.next(&lanes, &lane_mask); ++pi) {
        tests += lanes;
        __m128 tv, b1v, b2v;
        const int mask = packet_test(wide_.packets[pi], wr, t_min, _mm_set1_ps(r.max_t), &tv, &b1v, &b2v) & lane_mask;
        if (mask != 0) {
          alignas(16) float t[4], b1[4], b2[4];
          _mm_store_ps(t, tv);
          _mm_store_ps(b1, b1v);
          _mm_store_ps(b2, b2v);
          const int lane = nearest_lane(mask, t);
          prefetch_shading(scene_.triangles, wide_.packets[pi].id[lane]);
          r.max_t = t[lane];
          best_packet = pi;
          best_lane = lane;
          best_is_sphere = false;
          best_b1 = b1[lane];
          best_b2 = b2[lane];
        }
        if (wide_.has_spheres) {
          for (int lane = 0; lane < 4; ++lane) {
            const uint32_t id = wide_.packets[pi].id[lane];
            if ((lane_mask >> lane & 1) && id >= num_triangles_ &&
                intersect_sphere(scene_.spheres[id - num_triangles_], r, &sphere_hit)) {
              best_packet = pi;
              best_lane = lane;
              best_is_sphere = true;
            }
          }
        }
      }
    }
    // Next: the nearest pushed entry that starts before the nearest hit.
    // Nothing in a box entered at or beyond it can be strictly nearer.
    do {
      if (sp == 0) goto done;
      cur = stack[--sp];
    } while (cur.t >= r.max_t);
  }
done:
  stats.primitive_tests += tests;
  stats.node_visits += visits;
  if (best_lane < 0) return false;
  if (hit) {
    const uint32_t id = wide_.packets[best_packet].id[best_lane];
    if (!best_is_sphere) {
      const Triangle& tri = scene_.triangles[id];
      hit->t = r.max_t;
      hit->n = normalize(tri.n1 * (1.0f - best_b1 - best_b2) + tri.n2 * best_b1 + tri.n3 * best_b2);
      hit->material = tri.material;
    } else {
      *hit = sphere_hit;
    }
    hit->primitive = int(id);
  }
  return true;
  // END SOLUTION
}

bool BVH::occluded(const Ray& ray) const {
  RayStats& stats = thread_ray_stats();
  ++stats.shadow_queries;
  if (nodes_.empty()) return false;
  Ray r = ray;
  // BEGIN SOLUTION
  // STUB: PT_TODO_AS(2, "BVH::occluded", "every shadow ray tests every primitive");
  // STUB: return any_primitive_occludes(scene_, r);
  // Read from `ray`, not from its copy `r`, which is then never made: it is
  // copied 16 bytes at a time (see WideRay for why that stalls).
  (void)r;
  const WideRay wr(ray);
  if (!wr.finite) return false;
  const __m128 t_min = _mm_set1_ps(ray.min_t), t_max = _mm_set1_ps(ray.max_t);
  uint64_t tests = 0, visits = 0;
  bool found = false;
  WideEntry stack[kStackSize];
  int sp = 0;
  WideEntry cur{0, wide_.root_count, ray.min_t};
  for (;;) {
    ++visits;
    if (cur.count == 0) {
      // Interior: go on to the farthest child hit and push the others,
      // nearest first (bvh_wide.h says why far first).
      const WideNode& n = wide_.nodes[cur.child];
      alignas(16) float t[kWideWidth];
      const int mask = wide_box_test(n, wr, t_min, t_max, t);
      if (mask != 0) {
        cur = enter_children(n, mask, t, std::greater<float>(), stack, sp);
        continue;
      }
    } else {
      LeafLanes leaf(cur.count);
      uint32_t lanes;
      int lane_mask;
      for (uint32_t pi = cur.child; !found && leaf.next(&lanes, &lane_mask); ++pi) {
        tests += lanes;
        __m128 tv, b1v, b2v;
        found = (packet_test(wide_.packets[pi], wr, t_min, t_max, &tv, &b1v, &b2v) & lane_mask) != 0;
        if (wide_.has_spheres) {
          for (int lane = 0; lane < 4 && !found; ++lane) {
            const uint32_t id = wide_.packets[pi].id[lane];
            if ((lane_mask >> lane & 1) && id >= num_triangles_) {
              Ray rs = ray;  // intersect_sphere shortens the ray it is given
              found = intersect_sphere(scene_.spheres[id - num_triangles_], rs, nullptr);
            }
          }
        }
      }
      if (found) break;  // any hit will do
    }
    if (sp == 0) break;
    cur = stack[--sp];
  }
  stats.primitive_tests += tests;
  stats.node_visits += visits;
  return found;
  // END SOLUTION
}

}  // namespace pt
