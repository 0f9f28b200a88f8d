// REFERENCE ONLY: the starter kit leaves this file out (the reference's fast
// path, not code students write) unless it gives part 2 solved.
// Part 2 (speed): the reference traces an 8-wide BVH collapsed from the binary
// SAH tree, with triangles stored four to a packet and tested in one pass.
//
// Why each piece pays (measured with instructors/bench/compare_embree.sh and callgrind,
// see docs/benchmarks.md):
//  - 8-wide nodes: a binary tree of depth 3 folded into one node, so a ray
//    takes about a third of the node steps, and each step tests eight boxes,
//    four at a time with one SSE operation per plane. The boxes are stored
//    SoA (all eight children's lo.x, then hi.x, ...) and the ray picks the
//    near and far plane of each axis from its direction's sign once, so the
//    test needs no min/max swap. A node is 256 bytes: four aligned cache
//    lines side by side, whose loads are issued together. On
//    the dragons a query is bound by the wait for each node step's memory,
//    so fewer steps pay more than the wider test costs: 8 children traced
//    7-55 % faster than 4 (the dragons' primary rays least,
//    their shadow rays most); 12 and 16 were faster on the bunny's bounce and
//    shadow rays but slower on the dragon's (docs/benchmarks.md).
//  - Triangle packets: a leaf's triangles (at most four by default) in SoA
//    (p1.x of all four, then p1.y, ...), tested with one SSE Moller-Trumbore,
//    the same arithmetic in the same order as the scalar test, so every t
//    and barycentric is bit for bit the scalar one. The SAH makes many
//    leaves of one or two triangles; sibling leaves (children of one wide
//    node) share a packet when they fit, each testing only its own lanes,
//    so the tests and counts are those of separate leaves but the packets
//    are full and side by side in memory (fewer cache lines per ray).
//  - No virtual call, no per-primitive branch: a packet's empty lanes and its
//    sphere lanes hold zero edges, whose determinant 0 rejects them; spheres
//    (rare) are tested one by one after the packet, only in scenes that have
//    them.
//  - Closest hit: the children a ray enters are pushed farthest first, so the
//    nearest is visited next; an entry popped beyond the nearest hit so far is
//    dropped. Any hit: the other way round, farthest first (toward the light,
//    for a shadow ray), and the first hit ends the query. In the closed
//    Cornell boxes far first visits 6 % fewer nodes on shadow rays and 25 %
//    fewer on bounce rays than child order, and near first 10-25 % more:
//    a ray that is blocked usually is so by the surface it ends on.
// The counters keep their definitions: one node visit per wide node or leaf
// taken up, one primitive test per primitive of a leaf tested (empty lanes
// are not counted).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "common/bbox.h"
#include "common/ray.h"
#include "common/scene.h"

// SSE2 is part of x86-64, the project's baseline.
#if !defined(__SSE2__)
#error "the reference BVH (bvh_wide.h) needs SSE2: build for x86-64"
#endif
#include <emmintrin.h>


namespace pt {

// Children per node: a multiple of 4, the SSE width (8: see the top).
constexpr int kWideWidth = 8;

// kWideWidth children's boxes in SoA and where each child's subtree is.
struct alignas(64) WideNode {
  // Rows: lo.x, hi.x, lo.y, hi.y, lo.z, hi.z; column c is child c. An unused
  // slot holds the empty box (lo = +inf, hi = -inf), which no ray enters.
  float bounds[6][kWideWidth];
  // Interior child: count 0 and child = its node index. Leaf: child = its
  // first packet, count = its number of primitives (>= 1) in the low 24
  // bits and, in the top 8, the lane of that packet where it starts (small
  // sibling leaves share a packet, see WideBVH::collapse).
  uint32_t child[kWideWidth];
  uint32_t count[kWideWidth];
};

constexpr uint32_t kLeafCountMask = 0xffffff;
constexpr int kLeafLaneShift = 24;

// The lanes of a leaf's packets, one packet at a time: `lanes` of them from
// `first` on (a bit mask in `mask`).
struct LeafLanes {
  uint32_t left, first;
  explicit LeafLanes(uint32_t count) : left(count & kLeafCountMask), first(count >> kLeafLaneShift) {}
  // The next packet's lanes; false when the leaf has no more.
  bool next(uint32_t* lanes, int* mask) {
    if (left == 0) return false;
    *lanes = std::min<uint32_t>(4 - first, left);
    *mask = int(((1u << *lanes) - 1) << first);
    left -= *lanes;
    first = 0;
    return true;
  }
};
static_assert(sizeof(WideNode) == 32 * kWideWidth, "WideNode: whole cache lines");

// Four triangles in SoA, ready for Moller-Trumbore: p1 and the edges
// e1 = p2 - p1, e2 = p3 - p1. Unused lanes and sphere lanes are all zero.
// The lanes' primitive ids come last, in the cache line the test has just
// read: a closest hit needs its id to read the triangle's normals, and a
// separate array of ids cost one more cache miss per query (two dependent
// misses on a large mesh, about 10 % of a primary ray's time on the
// 200k-triangle dragon).
struct alignas(16) TrianglePacket {
  float p[3][4];
  float e1[3][4];
  float e2[3][4];
  uint32_t id[4];  // the primitive (triangles, then spheres), or WideBVH::kNoPrimitive
};
static_assert(sizeof(TrianglePacket) == 160, "TrianglePacket: three cache lines at most");

// A child reference as the traversal carries it: (child, count) as stored in
// WideNode, and the distance at which the ray enters its box.
struct WideEntry {
  uint32_t child;
  uint32_t count;
  float t;
};

struct WideBVH {
  std::vector<WideNode> nodes;             // nodes[0] is the root (unless the tree is one leaf)
  std::vector<TrianglePacket> packets;     // leaf order
  uint32_t root_count = 0;                 // 0: the root is nodes[0]; else the tree is one leaf (count as in WideNode)
  uint32_t num_triangles = 0;
  bool has_spheres = false;
  static constexpr uint32_t kNoPrimitive = 0xffffffffu;

  // Collapses a binary tree into this one. Node must have lo, hi, first,
  // count and is_leaf() (BVHNode): an interior node's children are
  // nodes[first] and nodes[first + 1]; a leaf holds leaf_ids[first ..
  // first + count). Each wide node takes the binary node's descendants of
  // largest surface area until it has kWideWidth children (the top of a subtree
  // is crossed by the most rays, so it is the part worth flattening).
  template <typename Node>
  void collapse(const std::vector<Node>& bin, const std::vector<uint32_t>& leaf_ids,
                const std::vector<Triangle>& triangles, size_t num_spheres) {
    nodes.clear();
    packets.clear();
    num_triangles = uint32_t(triangles.size());
    has_spheres = num_spheres > 0;
    root_count = 0;
    if (bin.empty()) return;
    nodes.reserve(bin.size() / 3 + 1);
    packets.reserve(leaf_ids.size() / 2 + 1);
    // Packs a leaf's primitives into packets: from lane `lane` of packet
    // `packet` on (a packet that has room), or into new packets.
    const auto new_packet = [&]() {
      packets.emplace_back();
      for (uint32_t& id : packets.back().id) id = kNoPrimitive;
      return uint32_t(packets.size() - 1);
    };
    // The tree is laid out first, with only the ids in the packets;
    // fill_lanes() then copies the triangles into them.
    const auto put = [&](uint32_t packet, uint32_t lane, uint32_t id) { packets[packet].id[lane] = id; };
    // Returns the leaf's (child, count) as WideNode stores them.
    uint32_t open_packet = 0, open_used = 4;  // the packet with room, and its lanes in use
    const auto pack_leaf = [&](const Node& leaf, uint32_t* count) {
      if (leaf.count <= 4) {  // one packet, shared with siblings when it fits
        if (open_used + leaf.count > 4) {
          open_packet = new_packet();
          open_used = 0;
        }
        for (uint32_t k = 0; k < leaf.count; ++k) put(open_packet, open_used + k, leaf_ids[leaf.first + k]);
        *count = leaf.count | (open_used << kLeafLaneShift);
        open_used += leaf.count;
        return open_packet;
      }
      const uint32_t first = uint32_t(packets.size());
      for (uint32_t k = 0; k < leaf.count; ++k) {
        if (k % 4 == 0) new_packet();
        put(first + k / 4, k % 4, leaf_ids[leaf.first + k]);
      }
      *count = leaf.count;
      return first;
    };
    if (bin[0].is_leaf()) {
      pack_leaf(bin[0], &root_count);
      fill_lanes(triangles);
      return;
    }
    // Depth first: a node's index is taken before its subtrees are made.
    struct Work {
      uint32_t bin_index, wide_index;
    };
    std::vector<Work> todo{{0, 0}};
    nodes.emplace_back();
    while (!todo.empty()) {
      const Work w = todo.back();
      todo.pop_back();
      uint32_t kids[kWideWidth] = {bin[w.bin_index].first, bin[w.bin_index].first + 1};
      int n = 2;
      while (n < kWideWidth) {  // open the interior child of largest area
        int pick = -1;
        float best = -1.0f;
        for (int c = 0; c < n; ++c) {
          const Node& k = bin[kids[c]];
          if (k.is_leaf()) continue;
          const float area = BBox(k.lo, k.hi).surface_area();
          if (area > best) {
            best = area;
            pick = c;
          }
        }
        if (pick < 0) break;
        const uint32_t first = bin[kids[pick]].first;
        kids[pick] = first;
        kids[n++] = first + 1;
      }
      WideNode out;
      for (int c = 0; c < kWideWidth; ++c) {
        for (int a = 0; a < 3; ++a) {
          out.bounds[2 * a][c] = c < n ? bin[kids[c]].lo[a] : INFINITY;
          out.bounds[2 * a + 1][c] = c < n ? bin[kids[c]].hi[a] : -INFINITY;
        }
        out.child[c] = 0;
        out.count[c] = 0;
      }
      // Leaves first, in child order (sharing packets among themselves, not
      // with another node's), then the interior children (pushed so that
      // the first is made first).
      open_used = 4;
      for (int c = 0; c < n; ++c) {
        const Node& k = bin[kids[c]];
        if (k.is_leaf()) out.child[c] = pack_leaf(k, &out.count[c]);
      }
      for (int c = n - 1; c >= 0; --c) {
        if (bin[kids[c]].is_leaf()) continue;
        out.child[c] = uint32_t(nodes.size());
        nodes.emplace_back();
        todo.push_back({kids[c], out.child[c]});
      }
      nodes[w.wide_index] = out;
    }
    fill_lanes(triangles);
  }

  // Copies each lane's triangle into its packet, in packet order. The
  // triangles are read in leaf order, which is random in the scene's
  // array: each is asked for a few lanes ahead, so that the cache misses
  // overlap (waiting for each triangle in turn made this loop cost more
  // than the rest of the collapse).
  void fill_lanes(const std::vector<Triangle>& triangles) {
    constexpr size_t kAhead = 16;
    const size_t n = 4 * packets.size();
    const auto triangle_of = [&](size_t i) -> const Triangle* {
      const uint32_t id = i < n ? packets[i / 4].id[i % 4] : kNoPrimitive;
      return id < num_triangles ? &triangles[id] : nullptr;
    };
    for (size_t i = 0; i < n; ++i) {
      if (const Triangle* ahead = triangle_of(i + kAhead)) {
        const char* bytes = reinterpret_cast<const char*>(ahead);
        _mm_prefetch(bytes, _MM_HINT_T0);
        _mm_prefetch(bytes + sizeof(Triangle) - 1, _MM_HINT_T0);
      }
      const Triangle* t = triangle_of(i);
      if (t == nullptr) continue;  // an empty or sphere lane: zero edges
      const Vec3 e1 = t->p2 - t->p1, e2 = t->p3 - t->p1;
      TrianglePacket& pk = packets[i / 4];
      const size_t lane = i % 4;
      for (int a = 0; a < 3; ++a) {
        pk.p[a][lane] = t->p1[a];
        pk.e1[a][lane] = e1[a];
        pk.e2[a][lane] = e2[a];
      }
    }
  }
};

// A ray prepared for the wide traversal: origin, reciprocal direction and
// direction broadcast to four lanes, and which row of a node's bounds is the
// near plane of each axis (lo when the direction is positive, else hi), as a
// byte offset into WideNode::bounds, ready to be added to a node's address. All
// computed for the three axes at once: a query's fixed cost matters, as two
// camera rays in three leave a Cornell box at its first node.
struct WideRay {
  __m128 o[3], inv[3], d[3];
  size_t near_offset[3], far_offset[3];  // row * (bytes per row)
  bool finite;  // origin and direction finite (a ray that is not hits nothing, as with brute force)
  explicit WideRay(const Ray& r) {
    // Loaded one float at a time: a 16-byte load of a ray its caller has just
    // written field by field waits for those stores to retire (no store
    // forwarding), a stall that cost 7 % of occluded()'s time in a render.
    const __m128 ov = _mm_movelh_ps(_mm_unpacklo_ps(_mm_load_ss(&r.o.x), _mm_load_ss(&r.o.y)), _mm_load_ss(&r.o.z));
    const __m128 dv = _mm_movelh_ps(_mm_unpacklo_ps(_mm_load_ss(&r.d.x), _mm_load_ss(&r.d.y)),
                                    _mm_unpacklo_ps(_mm_load_ss(&r.d.z), _mm_set_ss(1.0f)));
    const __m128 abs_mask = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
    const __m128 inf = _mm_set1_ps(INFINITY);
    const __m128 abs_d = _mm_and_ps(dv, abs_mask);
    finite = _mm_movemask_ps(_mm_and_ps(_mm_cmplt_ps(_mm_and_ps(ov, abs_mask), inf), _mm_cmplt_ps(abs_d, inf))) == 0xf;
    // Components of (almost) zero become +-1e-18, as Embree does: the
    // reciprocal stays finite, so (plane - o) * inv is never 0 * inf.
    const __m128 tiny = _mm_cmplt_ps(abs_d, _mm_set1_ps(1e-18f));
    const __m128 clamped = _mm_or_ps(_mm_andnot_ps(abs_mask, dv), _mm_set1_ps(1e-18f));
    const __m128 safe_d = _mm_or_ps(_mm_andnot_ps(tiny, dv), _mm_and_ps(tiny, clamped));
    const __m128 iv = _mm_div_ps(_mm_set1_ps(1.0f), safe_d);
    o[0] = _mm_shuffle_ps(ov, ov, 0x00);
    o[1] = _mm_shuffle_ps(ov, ov, 0x55);
    o[2] = _mm_shuffle_ps(ov, ov, 0xaa);
    d[0] = _mm_shuffle_ps(dv, dv, 0x00);
    d[1] = _mm_shuffle_ps(dv, dv, 0x55);
    d[2] = _mm_shuffle_ps(dv, dv, 0xaa);
    inv[0] = _mm_shuffle_ps(iv, iv, 0x00);
    inv[1] = _mm_shuffle_ps(iv, iv, 0x55);
    inv[2] = _mm_shuffle_ps(iv, iv, 0xaa);
    const size_t negative = size_t(_mm_movemask_ps(iv));
    constexpr size_t kRow = sizeof(float) * kWideWidth;
    for (size_t a = 0; a < 3; ++a) {
      const size_t neg = negative >> a & 1;
      near_offset[a] = (2 * a + neg) * kRow;
      far_offset[a] = (2 * a + 1 - neg) * kRow;
    }
  }
};

// The children's boxes against [t_min, t_max], four at a time: bit c of the
// result is set when the ray enters child c's box; t_enter[c] gets its entry
// distance.
inline int wide_box_test(const WideNode& n, const WideRay& r, __m128 t_min, __m128 t_max, float* t_enter) {
  int mask = 0;
  for (int half = 0; half < kWideWidth / 4; ++half) {
    const char* const rows = reinterpret_cast<const char*>(n.bounds) + 16 * half;
    const auto row = [rows](size_t offset) { return _mm_load_ps(reinterpret_cast<const float*>(rows + offset)); };
    const __m128 nx = _mm_mul_ps(_mm_sub_ps(row(r.near_offset[0]), r.o[0]), r.inv[0]);
    const __m128 ny = _mm_mul_ps(_mm_sub_ps(row(r.near_offset[1]), r.o[1]), r.inv[1]);
    const __m128 nz = _mm_mul_ps(_mm_sub_ps(row(r.near_offset[2]), r.o[2]), r.inv[2]);
    const __m128 fx = _mm_mul_ps(_mm_sub_ps(row(r.far_offset[0]), r.o[0]), r.inv[0]);
    const __m128 fy = _mm_mul_ps(_mm_sub_ps(row(r.far_offset[1]), r.o[1]), r.inv[1]);
    const __m128 fz = _mm_mul_ps(_mm_sub_ps(row(r.far_offset[2]), r.o[2]), r.inv[2]);
    const __m128 tn = _mm_max_ps(_mm_max_ps(nx, ny), _mm_max_ps(nz, t_min));
    const __m128 tf = _mm_min_ps(_mm_min_ps(fx, fy), _mm_min_ps(fz, t_max));
    _mm_store_ps(t_enter + 4 * half, tn);
    mask |= _mm_movemask_ps(_mm_cmple_ps(tn, tf)) << (4 * half);
  }
  return mask;
}

// Moller-Trumbore on four triangles at once, the arithmetic of the scalar
// test (bvh_traverse.cpp's hit_packed, part 1's intersect_triangle) in the
// same order, lane by lane. Returns the mask of lanes hit in [t_min, t_max]
// and their t and barycentrics.
inline int packet_test(const TrianglePacket& pk, const WideRay& r, __m128 t_min, __m128 t_max, __m128* t_out,
                       __m128* b1_out, __m128* b2_out) {
  const __m128 e1x = _mm_load_ps(pk.e1[0]), e1y = _mm_load_ps(pk.e1[1]), e1z = _mm_load_ps(pk.e1[2]);
  const __m128 e2x = _mm_load_ps(pk.e2[0]), e2y = _mm_load_ps(pk.e2[1]), e2z = _mm_load_ps(pk.e2[2]);
  const __m128 dx = r.d[0], dy = r.d[1], dz = r.d[2];
  // s1 = cross(d, e2); det = dot(s1, e1)
  const __m128 s1x = _mm_sub_ps(_mm_mul_ps(dy, e2z), _mm_mul_ps(dz, e2y));
  const __m128 s1y = _mm_sub_ps(_mm_mul_ps(dz, e2x), _mm_mul_ps(dx, e2z));
  const __m128 s1z = _mm_sub_ps(_mm_mul_ps(dx, e2y), _mm_mul_ps(dy, e2x));
  const __m128 det = _mm_add_ps(_mm_add_ps(_mm_mul_ps(s1x, e1x), _mm_mul_ps(s1y, e1y)), _mm_mul_ps(s1z, e1z));
  // det != 0 and finite (|det| < inf is false for NaN too)
  const __m128 abs_det = _mm_and_ps(det, _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff)));
  __m128 ok = _mm_and_ps(_mm_cmpneq_ps(det, _mm_setzero_ps()), _mm_cmplt_ps(abs_det, _mm_set1_ps(INFINITY)));
  const __m128 inv = _mm_div_ps(_mm_set1_ps(1.0f), det);
  // s = o - p1; b1 = dot(s1, s) / det
  const __m128 sx = _mm_sub_ps(r.o[0], _mm_load_ps(pk.p[0]));
  const __m128 sy = _mm_sub_ps(r.o[1], _mm_load_ps(pk.p[1]));
  const __m128 sz = _mm_sub_ps(r.o[2], _mm_load_ps(pk.p[2]));
  const __m128 b1 =
      _mm_mul_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(s1x, sx), _mm_mul_ps(s1y, sy)), _mm_mul_ps(s1z, sz)), inv);
  // s2 = cross(s, e1); b2 = dot(s2, d) / det; t = dot(s2, e2) / det
  const __m128 s2x = _mm_sub_ps(_mm_mul_ps(sy, e1z), _mm_mul_ps(sz, e1y));
  const __m128 s2y = _mm_sub_ps(_mm_mul_ps(sz, e1x), _mm_mul_ps(sx, e1z));
  const __m128 s2z = _mm_sub_ps(_mm_mul_ps(sx, e1y), _mm_mul_ps(sy, e1x));
  const __m128 b2 =
      _mm_mul_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(s2x, dx), _mm_mul_ps(s2y, dy)), _mm_mul_ps(s2z, dz)), inv);
  const __m128 t =
      _mm_mul_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(s2x, e2x), _mm_mul_ps(s2y, e2y)), _mm_mul_ps(s2z, e2z)), inv);
  // The scalar test's rejections, written the same way (a NaN rejects
  // nothing there, so it rejects nothing here): b1 < 0, b1 > 1, b2 < 0,
  // b1 + b2 > 1; and t must lie in [t_min, t_max].
  const __m128 zero = _mm_setzero_ps(), one = _mm_set1_ps(1.0f);
  const __m128 reject = _mm_or_ps(_mm_or_ps(_mm_cmplt_ps(b1, zero), _mm_cmpgt_ps(b1, one)),
                                  _mm_or_ps(_mm_cmplt_ps(b2, zero), _mm_cmpgt_ps(_mm_add_ps(b1, b2), one)));
  ok = _mm_and_ps(ok, _mm_and_ps(_mm_cmpge_ps(t, t_min), _mm_cmple_ps(t, t_max)));
  ok = _mm_andnot_ps(reject, ok);
  *t_out = t;
  *b1_out = b1;
  *b2_out = b2;
  return _mm_movemask_ps(ok);
}

}  // namespace pt
