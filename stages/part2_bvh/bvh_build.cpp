// Part 2, task 1: building the BVH with the binned surface area heuristic.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <thread>

#include "stages/part2_bvh/bvh.h"
// BEGIN SOLUTION
#include "stages/part2_bvh/bvh_binning.h"
// END SOLUTION
#include "common/todo.h"

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
// Past this depth splits are at the object median, which bounds the depth
// (and so the traversal stacks) whatever the primitives' layout: at most
// 96 + 32 levels.
constexpr int kMedianDepth = 96;
// The build in parallel: the top of the tree is built first, on one thread,
// down to subtrees of at most max(kTaskMin, n / kTasks) primitives; those
// are then built by all the threads, each into an array of its own, and
// appended in a fixed order. The split into subtrees depends on the scene
// alone, so the tree is the same for any number of threads. (Splitting the
// threads at the root instead gained 10 % on the dragons: a Cornell box's
// first splits cut 14 % or less off the mesh, so one thread did the rest.)
constexpr size_t kTaskMin = 4096;
constexpr size_t kTasks = 64;

// What a finished subtree adds to the statistics. Summed bottom-up, so the
// totals are the same whichever thread built which subtree.
struct SubtreeStats {
  double sah = 0;  // sum of area / root area over interior nodes, times the count over leaves
  size_t leaves = 0;
  int depth = 0;  // deepest leaf below the subtree's root (0: the root is a leaf)
};

struct Builder {
  const BVHOptions& opt;
  std::vector<PrimInfo>& prims;
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

  SubtreeStats make_leaf(BVHNode& n, size_t begin, size_t end, const BBox& box) const {
    n.lo = box.lo;
    n.hi = box.hi;
    n.first = uint32_t(begin);
    n.count = uint32_t(end - begin);
    SubtreeStats s;
    s.sah = double(box.surface_area()) / root_area * double(end - begin);
    s.leaves = 1;
    return s;
  }

  // A subtree left for later by the first phase of a parallel build.
  struct Task {
    uint32_t index;  // its root's place in the top part
    size_t begin, end;
    BBox box, cbox;
    int depth;
    std::vector<BVHNode> nodes;  // built: its root at 0, its other nodes after
    SubtreeStats stats;
  };
  std::vector<Task>* tasks = nullptr;  // first phase: subtrees of at most `grain` primitives are left here
  size_t grain = 0;

  // Builds the subtree of prims[begin, end) (box `box`, centroid box
  // `cbox`) into nodes[index], appending its descendants to `nodes`. The
  // children of a node are made as a pair (left, left + 1), then built one
  // after the other.
  SubtreeStats build(std::vector<BVHNode>& nodes, uint32_t index, size_t begin, size_t end, const BBox& box,
                     const BBox& cbox, int depth) const {
    const size_t count = end - begin;
    if (tasks && count <= grain) {  // for the second phase
      tasks->push_back(Task{index, begin, end, box, cbox, depth, {}, {}});
      return SubtreeStats{};
    }
    if (count == 1) return make_leaf(nodes[index], begin, end, box);

    // The SAH: cost(split) = A_left N_left + A_right N_right. Near the
    // leaves every split between sorted centroids is tried (exact, and
    // cheaper than clearing and sweeping the bins for a handful of
    // primitives); above, binned over all three axes in one pass over the
    // primitives (bvh_binning.h, with SSE).
    const int nb = std::max(2, std::min(opt.bins, kMaxSahBins));
    const Vec3 cext = cbox.extent();
    Vec3 scale;
    for (int a = 0; a < 3; ++a) scale[a] = cext[a] > 0 ? float(nb) / cext[a] : 0.0f;
    uint32_t sweep_order[kMaxSweep];
    const bool sweep = count <= kMaxSweep;
    const SahSplit split = sweep ? sah_sweep_split(&prims[begin], sizeof(PrimInfo), count, sweep_order)
                                 : sah_best_split(&prims[begin], sizeof(PrimInfo), count, cbox, scale, nb);
    const int best_axis = split.axis;
    const float best_cost = split.cost;

    // Leaves of at most max_leaf_size primitives are made when the SAH
    // prices them below the best split: n * C_isect against
    // C_trav + (A_left N_left + A_right N_right) / A * C_isect.
    // (The reference tests a leaf's triangles four at a time, so leaves of
    // four, C_leaf = ceil(n / 4), would trace 5-10 % faster; but the grader
    // judges a student's primitive tests per query against the reference's,
    // 8x + 4 at most, and with leaves of four the reference's counts on the
    // small scenes rose until a linear shadow scan fit under that limit.
    // The counts stay those of the tree a student builds.)
    if (count <= size_t(opt.max_leaf_size)) {
      const float area = box.surface_area();
      const float split_cost = opt.traversal_cost + (area > 0 ? best_cost / area : 0.0f);
      if (best_axis < 0 || float(count) <= split_cost) return make_leaf(nodes[index], begin, end, box);
    }

    // Partition at the best split, taking the children's centroid boxes on
    // the way (so no child needs a pass of its own to find them).
    size_t mid = begin;
    BBox lbox = split.left, rbox = split.right, lcbox, rcbox;
    if (sweep && best_axis >= 0) {
      PrimInfo sorted[kMaxSweep];
      for (size_t i = 0; i < count; ++i) sorted[i] = prims[begin + sweep_order[i]];
      std::copy(sorted, sorted + count, prims.begin() + long(begin));
      mid = begin + size_t(split.bin) + 1;
      BBox unused;
      bounds(begin, mid, &unused, &lcbox);
      bounds(mid, end, &unused, &rcbox);
    } else if (depth < kMedianDepth && best_axis >= 0) {
      mid = begin + sah_partition(&prims[begin], count, cbox, scale, nb, split, &lcbox, &rcbox);
    }
    if (mid == begin || mid == end) {
      // No usable split (all centroids in one place, or too deep): halve
      // the list, which still bounds the leaf size.
      mid = begin + count / 2;
      bounds(begin, mid, &lbox, &lcbox);
      bounds(mid, end, &rbox, &rcbox);
    }

    const uint32_t left = uint32_t(nodes.size());
    nodes.emplace_back();
    nodes.emplace_back();
    BVHNode& n = nodes[index];
    n.lo = box.lo;
    n.hi = box.hi;
    n.first = left;
    n.count = 0;
    const SubtreeStats ls = build(nodes, left, begin, mid, lbox, lcbox, depth + 1);
    const SubtreeStats rs = build(nodes, left + 1, mid, end, rbox, rcbox, depth + 1);
    SubtreeStats s;
    s.sah = double(box.surface_area()) / root_area + ls.sah + rs.sah;
    s.leaves = ls.leaves + rs.leaves;
    s.depth = 1 + std::max(ls.depth, rs.depth);
    return s;
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
    // STUB: PT_TODO_AS(2, "BVH construction", "one leaf holds every primitive");
    // STUB: unused(options);
    // STUB: nodes_.resize(1);
    // STUB: BBox all;
    // STUB: for (const PrimInfo& p : prims) all.expand(BBox(p.lo, p.hi));
    // STUB: nodes_[0].lo = all.lo;
    // STUB: nodes_[0].hi = all.hi;
    // STUB: nodes_[0].first = 0;
    // STUB: nodes_[0].count = uint32_t(prims.size());
    // STUB: stats_.nodes = 1;
    // STUB: stats_.leaves = 1;
    // STUB: stats_.sah_cost = double(prims.size());
    Builder b{options, prims};
    BBox all, call;
    b.bounds(0, prims.size(), &all, &call);
    b.root_area = std::max(double(all.surface_area()), 1e-30);
    nodes_.reserve(2 * prims.size());
    nodes_.resize(1);  // the root
    // First phase: the top of the tree, leaving the subtrees below the
    // grain as tasks.
    std::vector<Builder::Task> tasks;
    b.tasks = &tasks;
    b.grain = std::max(kTaskMin, prims.size() / kTasks);
    SubtreeStats s = b.build(nodes_, 0, 0, prims.size(), all, call, 0);
    // Second phase: the tasks, largest first, on all the machine's threads
    // by default (they touch disjoint ranges of prims).
    b.tasks = nullptr;
    int threads = options.build_threads > 0 ? options.build_threads : int(std::thread::hardware_concurrency());
    threads = std::max(1, std::min({threads, 64, int(tasks.size())}));
    std::vector<size_t> order(tasks.size());
    for (size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::stable_sort(order.begin(), order.end(), [&](size_t x, size_t y) {
      return tasks[x].end - tasks[x].begin > tasks[y].end - tasks[y].begin;
    });
    std::atomic<size_t> next{0};
    const auto work = [&] {
      for (size_t k; (k = next.fetch_add(1)) < order.size();) {
        Builder::Task& t = tasks[order[k]];
        t.nodes.reserve(2 * (t.end - t.begin));
        t.nodes.resize(1);
        t.stats = b.build(t.nodes, 0, t.begin, t.end, t.box, t.cbox, t.depth);
      }
    };
    std::vector<std::thread> helpers;
    for (int k = 1; k < threads; ++k) helpers.emplace_back(work);
    work();
    for (std::thread& h : helpers) h.join();
    // Each task's nodes appended in task order (the order the first phase
    // met them), its root put in its place; statistics summed in that order.
    for (Builder::Task& t : tasks) {
      const uint32_t offset = uint32_t(nodes_.size()) - 1;  // t.nodes[k] -> nodes_[offset + k], k >= 1
      for (BVHNode& m : t.nodes)
        if (!m.is_leaf()) m.first += offset;
      nodes_[t.index] = t.nodes[0];
      nodes_.insert(nodes_.end(), t.nodes.begin() + 1, t.nodes.end());
      s.sah += t.stats.sah;
      s.leaves += t.stats.leaves;
      s.depth = std::max(s.depth, t.depth + t.stats.depth);
    }
    stats_.nodes = nodes_.size();
    stats_.leaves = s.leaves;
    stats_.depth = s.depth;
    stats_.sah_cost = s.sah;
    // END SOLUTION
  }

  // Primitives in leaf order, triangles packed for the intersection test.
  prim_ids_.resize(prims.size());
  for (size_t i = 0; i < prims.size(); ++i) prim_ids_[i] = prims[i].id;
  // BEGIN SOLUTION
  // STUB: tris_.resize(prims.size());
  // STUB: for (size_t i = 0; i < prims.size(); ++i) {
  // STUB:   if (prim_ids_[i] >= nt) continue;  // a sphere
  // STUB:   const Triangle& t = scene_.triangles[prim_ids_[i]];
  // STUB:   tris_[i] = PackedTriangle{t.p1, t.p2 - t.p1, t.p3 - t.p1};
  // STUB: }
  // The reference packs its triangles four to a packet instead (bvh_wide.h),
  // and reads each triangle once: filling tris_ too, in leaf order, cost a
  // random read of every triangle (about 5 % of the large dragon's build).
  (void)nt;
  wide_.collapse(nodes_, prim_ids_, scene_.triangles, scene_.spheres.size());
  // END SOLUTION
  stats_.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

BVH::BVH(const Scene& scene, const BVHOptions& options) : scene_(scene) { build(options); }

}  // namespace pt
