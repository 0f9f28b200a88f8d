// Part 2: the bounding volume hierarchy.
//
// What the rest of the renderer sees is the interface: the constructor
// builds, intersect() and occluded() answer, bounds() and build_stats()
// describe the tree. How the tree is stored is yours: the members below are
// a suggestion (a flat array of 32-byte nodes, primitives reordered into
// leaf order, triangles stored as a point and two edges), and you may change
// BVHNode and the private members as you like.
#pragma once
#include <cstdint>
#include <vector>

#include "common/intersector.h"
#include "common/scene.h"
// BEGIN SOLUTION
#include "stages/part2_bvh/bvh_wide.h"
// END SOLUTION

namespace pt {

// A suggested node: its box, and either its children or its primitives.
struct BVHNode {
  Vec3 lo;
  uint32_t first = 0;  // interior: index of the left child (right = first + 1); leaf: first entry of prim_ids_
  Vec3 hi;
  uint32_t count = 0;  // 0 for an interior node, else the number of primitives in the leaf

  bool is_leaf() const { return count != 0; }
};

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

  // What the build made: nodes, leaves, depth, SAH cost, build time.
  const BVHBuildStats& build_stats() const { return stats_; }
  // The box of the whole scene (empty for an empty scene).
  BBox bounds() const { return nodes_.empty() ? BBox() : BBox(nodes_[0].lo, nodes_[0].hi); }
  // The tree in the suggested form, for the viewer's BVH mode and the
  // write-up's BVH figures, which draw it box by box: nodes()[0] is the
  // root, an interior node's children are nodes()[first] and
  // nodes()[first + 1], and a leaf's primitives are leaf_primitives()[first]
  // to [first + count - 1] (ids as above: triangles, then spheres). If you
  // store your tree another way, fill these in that form after the build.
  const std::vector<BVHNode>& nodes() const { return nodes_; }
  const std::vector<uint32_t>& leaf_primitives() const { return prim_ids_; }
  // BEGIN SOLUTION
  // The reference's 8-wide tree, for its layout tests (tests/part2).
  const WideBVH& wide() const { return wide_; }
  // END SOLUTION

 private:
  void build(const BVHOptions& options);

  const Scene& scene_;
  uint32_t num_triangles_ = 0;
  // Suggested layout: nodes_[0] is the root. prim_ids_ holds primitive ids
  // in leaf order (id < num_triangles_: a triangle, else the sphere
  // id - num_triangles_), and tris_ the triangles in the same order.
  std::vector<BVHNode> nodes_;
  std::vector<uint32_t> prim_ids_;
  std::vector<PackedTriangle> tris_;
  BVHBuildStats stats_;
  // BEGIN SOLUTION
  WideBVH wide_;  // the reference's fast path: the tree above, collapsed 8-wide (bvh_wide.h)
  // END SOLUTION
};

}  // namespace pt
