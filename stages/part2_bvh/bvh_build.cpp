// Part 2, task 1: building the BVH with the binned surface area heuristic.
#include <algorithm>
#include <chrono>
#include <cmath>

#include "bvh.h"
#include "todo.h"

namespace pt {

namespace {

// What the builder knows of each primitive: its box, its centroid and id.
struct PrimInfo {
  Vec3 lo;
  uint32_t id;
  Vec3 hi;
  float pad;
  Vec3 centroid() const { return (lo + hi) * 0.5f; }
};

// BEGIN SOLUTION
constexpr int kMedianDepth = 96;

// The bin of a centroid coordinate: (c - lo) * scale cut to [0, nb - 1].
// The comparisons come before the conversion to int, which is undefined
// for NaN and for values beyond int's range (a scene whose coordinates
// reach 1e38 makes both).
inline int bin_of(float c, float lo, float scale, int nb) {
  const float f = (c - lo) * scale;
  if (!(f > 0.0f)) return 0;
  if (f >= float(nb - 1)) return nb - 1;
  return int(f);
}

struct Builder {
  const BVHOptions& opt;
  std::vector<PrimInfo>& prims;
  std::vector<BVHNode>& nodes;
  BVHBuildStats& stats;
  double root_area = 1;

  // Box of prims[begin, end) and box of their centroids.
  void bounds(size_t begin, size_t end, BBox* box, BBox* cbox) const {
    BBox b, c;
    for (size_t i = begin; i < end; ++i) {
      b.lo = vmin(b.lo, prims[i].lo);
      b.hi = vmax(b.hi, prims[i].hi);
      c.expand(prims[i].centroid());
    }
    *box = b;
    *cbox = c;
  }

  void make_leaf(uint32_t index, size_t begin, size_t end, const BBox& box, int depth) {
    BVHNode& n = nodes[index];
    n.lo = box.lo;
    n.hi = box.hi;
    n.first = uint32_t(begin);
    n.count = uint32_t(end - begin);
    ++stats.leaves;
    stats.depth = std::max(stats.depth, depth);
    stats.sah_cost += double(box.surface_area()) / root_area * double(end - begin);
  }

  // Builds the subtree of prims[begin, end) into nodes[index].
  void build(uint32_t index, size_t begin, size_t end, int depth) {
    BBox box, cbox;
    bounds(begin, end, &box, &cbox);
    const size_t count = end - begin;
    if (count == 1) {
      make_leaf(index, begin, end, box, depth);
      return;
    }

    // Binned SAH over all three axes: cost(split) = A_left N_left + A_right N_right.
    const int nb = std::max(2, std::min(opt.bins, 64));
    int best_axis = -1, best_bin = 0;
    float best_cost = INFINITY;
    const Vec3 cext = cbox.extent();
    for (int axis = 0; axis < 3; ++axis) {
      const float lo = cbox.lo[axis], ext = cext[axis];
      if (!(ext > 0)) continue;  // all centroids equal along this axis
      const float scale = float(nb) / ext;
      BBox bin_box[64];
      size_t bin_count[64] = {};
      for (size_t i = begin; i < end; ++i) {
        const int b = bin_of(prims[i].centroid()[axis], lo, scale, nb);
        ++bin_count[b];
        bin_box[b].lo = vmin(bin_box[b].lo, prims[i].lo);
        bin_box[b].hi = vmax(bin_box[b].hi, prims[i].hi);
      }
      // Sweep from the right: area and count of bins [b, nb).
      float right_area[64];
      size_t right_count[64];
      BBox acc;
      size_t n = 0;
      for (int b = nb - 1; b > 0; --b) {
        acc.expand(bin_box[b]);
        n += bin_count[b];
        right_area[b] = acc.surface_area();
        right_count[b] = n;
      }
      acc = BBox();
      n = 0;
      for (int b = 0; b < nb - 1; ++b) {  // split between bin b and b + 1
        acc.expand(bin_box[b]);
        n += bin_count[b];
        if (n == 0 || right_count[b + 1] == 0) continue;
        const float cost = acc.surface_area() * float(n) + right_area[b + 1] * float(right_count[b + 1]);
        if (cost < best_cost) {
          best_cost = cost;
          best_axis = axis;
          best_bin = b;
        }
      }
    }

    // Leaves of at most max_leaf_size primitives are made when the SAH
    // prices them below the best split: n * C_isect against
    // C_trav + (A_left N_left + A_right N_right) / A * C_isect.
    if (count <= size_t(opt.max_leaf_size)) {
      const float area = box.surface_area();
      const float split_cost = opt.traversal_cost + (area > 0 ? best_cost / area : 0.0f);
      if (best_axis < 0 || float(count) <= split_cost) {
        make_leaf(index, begin, end, box, depth);
        return;
      }
    }

    size_t mid = begin + count / 2;
    // Past a generous depth, split at the object median: it bounds the depth
    // (and so the traversal stack) whatever the primitives' layout.
    if (depth >= kMedianDepth) best_axis = -1;
    if (best_axis >= 0) {
      const float lo = cbox.lo[best_axis], scale = float(nb) / cext[best_axis];
      auto left_of_split = [&](const PrimInfo& p) { return bin_of(p.centroid()[best_axis], lo, scale, nb) <= best_bin; };
      mid = size_t(std::partition(prims.begin() + long(begin), prims.begin() + long(end), left_of_split) -
                   prims.begin());
    }
    if (mid == begin || mid == end) {
      // No usable split (all centroids in one place): halve the list, which
      // still bounds the leaf size.
      mid = begin + count / 2;
    }

    const uint32_t left = uint32_t(nodes.size());
    nodes.emplace_back();
    nodes.emplace_back();
    BVHNode& n = nodes[index];
    n.lo = box.lo;
    n.hi = box.hi;
    n.first = left;
    n.count = 0;
    stats.sah_cost += double(box.surface_area()) / root_area;
    build(left, begin, mid, depth + 1);
    build(left + 1, mid, end, depth + 1);
  }
};
// END SOLUTION

}  // namespace

void BVH::build(const BVHOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  const size_t nt = scene_.triangles.size(), ns = scene_.spheres.size();
  num_triangles_ = uint32_t(nt);
  std::vector<PrimInfo> prims(nt + ns);
  for (size_t i = 0; i < nt; ++i) {
    const BBox b = scene_.triangles[i].bounds();
    prims[i] = PrimInfo{b.lo, uint32_t(i), b.hi, 0.0f};
  }
  for (size_t i = 0; i < ns; ++i) {
    const BBox b = scene_.spheres[i].bounds();
    prims[nt + i] = PrimInfo{b.lo, uint32_t(nt + i), b.hi, 0.0f};
  }

  nodes_.clear();
  stats_ = BVHBuildStats{};
  if (!prims.empty()) {
    // BEGIN SOLUTION
    // STUB: todo_once("Part 2: BVH construction (stages/part2_bvh/bvh_build.cpp); using one leaf");
    // STUB: (void)options;
    // STUB: nodes_.resize(2);
    // STUB: BBox all;
    // STUB: for (const PrimInfo& p : prims) all.expand(BBox(p.lo, p.hi));
    // STUB: nodes_[0].lo = all.lo;
    // STUB: nodes_[0].hi = all.hi;
    // STUB: nodes_[0].first = 0;
    // STUB: nodes_[0].count = uint32_t(prims.size());
    // STUB: stats_.leaves = 1;
    // STUB: stats_.sah_cost = double(prims.size());
    nodes_.reserve(2 * (prims.size() / size_t(std::max(1, options.max_leaf_size / 2)) + 1) + 2);
    nodes_.resize(2);  // the root, and padding so that sibling pairs start at even indices
    Builder b{options, prims, nodes_, stats_};
    BBox all, call;
    b.bounds(0, prims.size(), &all, &call);
    b.root_area = std::max(double(all.surface_area()), 1e-30);
    b.build(0, 0, prims.size(), 0);
    // END SOLUTION
  }
  stats_.nodes = nodes_.empty() ? 0 : nodes_.size() - 1;

  // Primitives in leaf order, triangles packed for the intersection test.
  prim_ids_.resize(prims.size());
  tris_.resize(prims.size());
  for (size_t i = 0; i < prims.size(); ++i) {
    const uint32_t id = prims[i].id;
    prim_ids_[i] = id;
    if (id < nt) {
      const Triangle& t = scene_.triangles[id];
      tris_[i] = PackedTriangle{t.p1, t.p2 - t.p1, t.p3 - t.p1};
    }
  }
  // BEGIN SOLUTION
  wide_.collapse(nodes_, prim_ids_, scene_.triangles, scene_.spheres.size());
  // END SOLUTION
  stats_.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

BVH::BVH(const Scene& scene, const BVHOptions& options) : scene_(scene) { build(options); }

}  // namespace pt
