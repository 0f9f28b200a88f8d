// Part 2: the bounding volume hierarchy.
//
// Layout (why it is fast): one flat array of 32-byte nodes; the two children
// of a node are adjacent and start at an even index, so a sibling pair is
// one 64-byte cache line. Primitives are reordered into leaf order and
// triangles are stored as (p1, e1, e2), 36 bytes, so a leaf's triangles are
// contiguous. Traversal visits the nearer child first with an explicit
// stack and skips nodes that start beyond the current hit; shadow rays use
// a separate early-exit query. Triangles and spheres share the tree; a leaf
// entry's id says which one it is (no virtual call per primitive).
#pragma once
#include <cstdint>
#include <vector>

#include "intersector.h"
#include "scene.h"
// BEGIN SOLUTION
#include "bvh_wide.h"
// END SOLUTION

namespace pt {

struct BVHNode {
  Vec3 lo;
  uint32_t first = 0;  // interior: index of the left child (right = first + 1); leaf: first entry
  Vec3 hi;
  uint32_t count = 0;  // 0 for an interior node, else the number of primitives in the leaf

  bool is_leaf() const { return count != 0; }
};
static_assert(sizeof(BVHNode) == 32, "BVHNode must be 32 bytes");

struct BVHOptions {
  int max_leaf_size = 4;  // leaves hold at most this many primitives
  int bins = 12;          // SAH bins per axis
  float traversal_cost = 1.0f;  // SAH: cost of visiting a node relative to one primitive test
  int build_threads = 0;  // threads the build may use; 0: all the machine's (a builder may ignore it)
};

struct BVHBuildStats {
  double build_seconds = 0;
  size_t nodes = 0;       // nodes in the tree (interior + leaves)
  size_t leaves = 0;
  int depth = 0;          // deepest leaf (root = 0)
  double sah_cost = 0;    // expected cost per ray: traversal 1, primitive test 1, relative to the root's area
};

// A triangle ready for Moller-Trumbore: p1 and the two edges from it.
struct PackedTriangle {
  Vec3 p1, e1, e2;
};

class BVH final : public Intersector {
 public:
  BVH(const Scene& scene, const BVHOptions& options = {});

  bool intersect(Ray& r, Hit* hit) const override;
  bool occluded(const Ray& r) const override;

  const BVHBuildStats& build_stats() const { return stats_; }
  const std::vector<BVHNode>& nodes() const { return nodes_; }
  // Primitive ids in leaf order: id < num_triangles is a triangle, else a
  // sphere (id - num_triangles). A leaf holds entries [first, first + count).
  const std::vector<uint32_t>& leaf_primitives() const { return prim_ids_; }
  const BBox bounds() const { return nodes_.empty() ? BBox() : BBox(nodes_[0].lo, nodes_[0].hi); }

 private:
  void build(const BVHOptions& options);

  const Scene& scene_;
  uint32_t num_triangles_ = 0;
  std::vector<BVHNode> nodes_;         // nodes_[0] is the root; nodes_[1] is unused padding
  std::vector<uint32_t> prim_ids_;     // leaf order
  std::vector<PackedTriangle> tris_;   // leaf order, parallel to prim_ids_ (unused for spheres)
  BVHBuildStats stats_;
  // BEGIN SOLUTION
  WideBVH wide_;  // the reference's fast path: the tree above, collapsed 4-wide (bvh_wide.h)
  // END SOLUTION
};

}  // namespace pt
