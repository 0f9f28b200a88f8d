// Part 2, task 3: closest-hit and occlusion queries through the BVH.
#include <cmath>

#include "brute_force.h"
#include "bvh.h"
#include "slab_test.h"
// BEGIN SOLUTION
#include "slab_test_pair.h"
// END SOLUTION
#include "sphere.h"
#include "stats.h"
#include "todo.h"
#include "triangle.h"

namespace pt {

namespace {

// BEGIN SOLUTION
// Moller-Trumbore on a packed triangle; the same arithmetic as
// intersect_triangle, so both report the same t and barycentrics.
inline bool hit_packed(const PackedTriangle& tri, const Ray& r, float* t_out, float* b1_out, float* b2_out) {
  const Vec3 s1 = cross(r.d, tri.e2);
  const float det = dot(s1, tri.e1);
  if (det == 0.0f || !std::isfinite(det)) return false;
  const float inv = 1.0f / det;
  const Vec3 s = r.o - tri.p1;
  const float b1 = dot(s1, s) * inv;
  if (b1 < 0.0f || b1 > 1.0f) return false;
  const Vec3 s2 = cross(s, tri.e1);
  const float b2 = dot(s2, r.d) * inv;
  if (b2 < 0.0f || b1 + b2 > 1.0f) return false;
  const float t = dot(s2, tri.e2) * inv;
  if (!(t >= r.min_t && t <= r.max_t)) return false;
  *t_out = t;
  *b1_out = b1;
  *b2_out = b2;
  return true;
}

constexpr int kStackSize = 128;  // the builder keeps the tree shallower than this
// END SOLUTION

}  // namespace

bool BVH::intersect(Ray& r, Hit* hit) const {
  RayStats& stats = thread_ray_stats();
  ++stats.closest_queries;
  if (nodes_.empty()) return false;
  // BEGIN SOLUTION
  // STUB: PT_TODO_AS(2, "BVH::intersect", "testing every primitive");
  // STUB: return intersect_every_primitive(scene_, r, hit);
  const PairRay pray(r);
  uint64_t tests = 0, visits = 0;
  int best = -1;  // leaf-order index of the nearest primitive so far
  float best_b1 = 0, best_b2 = 0;
  Hit sphere_hit;

  struct Entry {
    uint32_t node;
    float t_enter;
  };
  Entry stack[kStackSize];
  int sp = 0;
  float t_root;
  if (slab_test(nodes_[0].lo, nodes_[0].hi, r.o, pray.inv, r.min_t, r.max_t, &t_root)) stack[sp++] = {0, t_root};

  while (sp > 0) {
    const Entry e = stack[--sp];
    // Nothing in a box entered at or beyond the nearest hit found since it
    // was pushed can be strictly nearer.
    if (e.t_enter >= r.max_t) continue;
    uint32_t ni = e.node;
    for (;;) {
      ++visits;
      const BVHNode& n = nodes_[ni];
      if (n.is_leaf()) {
        const uint32_t end = n.first + n.count;
        for (uint32_t i = n.first; i < end; ++i) {
          ++tests;
          if (prim_ids_[i] < num_triangles_) {
            float t, b1, b2;
            if (hit_packed(tris_[i], r, &t, &b1, &b2)) {
              r.max_t = t;
              best = int(i);
              best_b1 = b1;
              best_b2 = b2;
            }
          } else if (intersect_sphere(scene_.spheres[prim_ids_[i] - num_triangles_], r, &sphere_hit)) {
            best = int(i);
          }
        }
        break;
      }
      // Interior: test both children, go to the nearer, keep the other.
      float ta, tb;
      const int h = slab_test_pair(&nodes_[n.first], pray, r.min_t, r.max_t, &ta, &tb);
      const bool ha = h & 1, hb = h & 2;
      if (ha && hb) {
        if (ta <= tb) {
          stack[sp++] = {n.first + 1, tb};
          ni = n.first;
        } else {
          stack[sp++] = {n.first, ta};
          ni = n.first + 1;
        }
      } else if (ha) {
        ni = n.first;
      } else if (hb) {
        ni = n.first + 1;
      } else {
        break;
      }
    }
  }
  stats.primitive_tests += tests;
  stats.node_visits += visits;
  if (best < 0) return false;
  if (hit) {
    const uint32_t id = prim_ids_[size_t(best)];
    if (id < num_triangles_) {
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
  // STUB: PT_TODO_AS(2, "BVH::occluded", "testing every primitive");
  // STUB: return any_primitive_occludes(scene_, r);
  const PairRay pray(r);
  uint64_t tests = 0, visits = 0;
  bool found = false;
  uint32_t stack[kStackSize];
  int sp = 0;
  float t_enter;
  if (slab_test(nodes_[0].lo, nodes_[0].hi, r.o, pray.inv, r.min_t, r.max_t, &t_enter)) stack[sp++] = 0;
  while (sp > 0 && !found) {
    const BVHNode& n = nodes_[stack[--sp]];
    ++visits;
    if (n.is_leaf()) {
      const uint32_t end = n.first + n.count;
      for (uint32_t i = n.first; i < end; ++i) {
        ++tests;
        float t, b1, b2;
        const bool h = prim_ids_[i] < num_triangles_
                           ? hit_packed(tris_[i], r, &t, &b1, &b2)
                           : intersect_sphere(scene_.spheres[prim_ids_[i] - num_triangles_], r, nullptr);
        if (h) {
          found = true;  // any hit will do
          break;
        }
      }
      continue;
    }
    float ta, tb;
    const int h = slab_test_pair(&nodes_[n.first], pray, r.min_t, r.max_t, &ta, &tb);
    if (h & 2) stack[sp++] = n.first + 1;
    if (h & 1) stack[sp++] = n.first;
  }
  stats.primitive_tests += tests;
  stats.node_visits += visits;
  return found;
  // END SOLUTION
}

}  // namespace pt
