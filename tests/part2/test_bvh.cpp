// Part 2: the BVH's structure, and its answers against brute force.
#include <catch2/catch.hpp>
#include <functional>

#include "stages/part1_raytracing/brute_force.h"
#include "stages/part2_bvh/bvh.h"
#include "common/collada.h"
#include "common/rng.h"
#include "common/stats.h"
#include "tests/support.h"

using namespace pt;

namespace {

Triangle make_triangle(const Vec3& a, const Vec3& b, const Vec3& c) {
  Triangle t;
  t.p1 = a;
  t.p2 = b;
  t.p3 = c;
  const Vec3 n = normalize(cross(b - a, c - a));
  t.n1 = t.n2 = t.n3 = n;
  return t;
}

// A seeded soup of random triangles and a few spheres in [-1, 1]^3.
Scene random_scene(int triangles, int spheres, uint64_t seed) {
  Scene s;
  for (int m = 0; m < 3; ++m) s.materials.push_back(Material{});
  Rng rng(seed);
  const auto u = [&] { return rng.uniform() * 2.0f - 1.0f; };
  for (int i = 0; i < triangles; ++i) {
    const Vec3 c(u(), u(), u());
    const float size = 0.02f + 0.2f * rng.uniform();
    Triangle t = make_triangle(c + Vec3(u(), u(), u()) * size, c + Vec3(u(), u(), u()) * size,
                               c + Vec3(u(), u(), u()) * size);
    // Three different vertex normals and a material of its own, so a hit
    // that reports another vertex's normal or the wrong material shows.
    t.n1 = normalize(t.n1 + Vec3(0.3f, 0, 0));
    t.n2 = normalize(t.n2 + Vec3(0, 0.3f, 0));
    t.n3 = normalize(t.n3 + Vec3(0, 0, 0.3f));
    t.material = i % 3;
    s.triangles.push_back(t);
  }
  for (int i = 0; i < spheres; ++i) s.spheres.push_back(Sphere{Vec3(u(), u(), u()), 0.05f + 0.1f * rng.uniform(), 0});
  return s;
}

bool box_contains(const BBox& outer, const BBox& inner) {
  return outer.lo.x <= inner.lo.x && outer.lo.y <= inner.lo.y && outer.lo.z <= inner.lo.z &&
         outer.hi.x >= inner.hi.x && outer.hi.y >= inner.hi.y && outer.hi.z >= inner.hi.z;
}

// Checks what the interface shows of the tree (a BVH's layout is its own):
// bounds() is the scene's box, exactly; the statistics are consistent with
// leaves of at most max_leaf primitives.
void check_interface(const Scene& scene, const BVH& bvh, int max_leaf) {
  BBox all;
  for (const Triangle& t : scene.triangles) all.expand(t.bounds());
  for (const Sphere& sp : scene.spheres) all.expand(sp.bounds());
  const BBox b = bvh.bounds();
  CHECK(b.lo == all.lo);
  CHECK(b.hi == all.hi);
  const BVHBuildStats& st = bvh.build_stats();
  const size_t n = scene.num_primitives();
  CHECK(st.leaves >= (n + size_t(max_leaf) - 1) / size_t(max_leaf));
  CHECK(st.leaves <= n);
  CHECK(st.nodes >= st.leaves);
  CHECK(st.sah_cost > 0);
  CHECK(st.build_seconds >= 0);
}

// BEGIN SOLUTION
// The reference's own layout (not a contract for students' BVHs). Binary
// tree: every primitive in exactly one leaf, boxes nest, leaf sizes
// respected. 8-wide tree collapsed from it: every primitive in exactly one
// packet lane, under boxes that hold it, each node's slots either used or
// empty boxes.
void check_reference_layout(const Scene& scene, const BVH& bvh, int max_leaf) {
  const auto& nodes = bvh.nodes();
  const auto& ids = bvh.leaf_primitives();
  const size_t n = scene.num_primitives();
  REQUIRE(ids.size() == n);
  const auto prim_box = [&](uint32_t id) {
    return id < scene.triangles.size() ? scene.triangles[id].bounds() : scene.spheres[id - scene.triangles.size()].bounds();
  };
  std::vector<int> seen(n, 0);
  size_t leaves_checked = 0;
  std::function<void(uint32_t)> visit = [&](uint32_t i) {
    REQUIRE(i < nodes.size());
    const BVHNode& node = nodes[i];
    if (node.is_leaf()) {
      CHECK(int(node.count) <= max_leaf);
      ++leaves_checked;
      for (uint32_t k = node.first; k < node.first + node.count; ++k) {
        REQUIRE(k < ids.size());
        REQUIRE(ids[k] < n);
        ++seen[ids[k]];
        CHECK(box_contains(BBox(node.lo, node.hi), prim_box(ids[k])));
      }
      return;
    }
    for (uint32_t c : {node.first, node.first + 1}) {
      CHECK(box_contains(BBox(node.lo, node.hi), BBox(nodes[c].lo, nodes[c].hi)));
      visit(c);
    }
  };
  if (n > 0) visit(0);
  for (size_t id = 0; id < n; ++id) {
    INFO("primitive " << id);
    CHECK(seen[id] == 1);
  }
  CHECK(leaves_checked == bvh.build_stats().leaves);
  CHECK(nodes.size() == bvh.build_stats().nodes);

  // The wide tree.
  const WideBVH& w = bvh.wide();
    std::vector<int> in_lane(n, 0);
  std::function<void(uint32_t, uint32_t, const BBox&)> visit_wide = [&](uint32_t child, uint32_t count,
                                                                        const BBox& box) {
    if (count > 0) {
      const uint32_t first_lane = count >> kLeafLaneShift, prims = count & kLeafCountMask;
      CHECK((prims <= 4 ? first_lane + prims <= 4 : first_lane == 0));
      for (uint32_t k = 0; k < prims; ++k) {
        const size_t slot = 4 * size_t(child) + first_lane + k;
        REQUIRE(slot < 4 * w.packets.size());
        const uint32_t id = w.packets[slot / 4].id[slot % 4];
        REQUIRE(id < n);
        ++in_lane[id];
        CHECK(box_contains(box, prim_box(id)));
        if (id < scene.triangles.size()) {  // the lane holds this triangle's p1 and edges
          const Triangle& t = scene.triangles[id];
          const TrianglePacket& pk = w.packets[slot / 4];
          const size_t lane = slot % 4;
          CHECK((pk.p[0][lane] == t.p1.x && pk.p[1][lane] == t.p1.y && pk.p[2][lane] == t.p1.z));
          CHECK((pk.e1[0][lane] == t.p2.x - t.p1.x && pk.e2[2][lane] == t.p3.z - t.p1.z));
        }
      }
      return;
    }
    REQUIRE(child < w.nodes.size());
    const WideNode& node = w.nodes[child];
    int used = 0;
    for (int c = 0; c < kWideWidth; ++c) {
      const BBox cb(Vec3(node.bounds[0][c], node.bounds[2][c], node.bounds[4][c]),
                    Vec3(node.bounds[1][c], node.bounds[3][c], node.bounds[5][c]));
      if (node.bounds[0][c] == INFINITY) {  // an empty slot
        CHECK(node.bounds[1][c] == -INFINITY);
        continue;
      }
      ++used;
      CHECK(box_contains(box, cb));
      visit_wide(node.child[c], node.count[c], cb);
    }
    CHECK(used >= 2);
  };
  if (n > 0) visit_wide(0, w.root_count, bvh.bounds());
  for (size_t id = 0; id < n; ++id) {
    INFO("primitive " << id << " in the wide tree");
    CHECK(in_lane[id] == 1);
  }
  // Every lane holding a primitive belongs to exactly one leaf (checked
  // above); the others are empty.
  size_t used_lanes = 0;
  for (const TrianglePacket& pk : w.packets)
    for (const uint32_t id : pk.id) used_lanes += id != WideBVH::kNoPrimitive;
  CHECK(used_lanes == n);
}
// END SOLUTION

// Random rays: origins in and around the scene (within `spread` of the
// centre), directions uniform on the sphere, or aimed at a random point of
// the scene when the origin is far; some with exactly zero components.
Ray random_ray(Rng& rng, float spread) {
  const auto u = [&] { return (rng.uniform() * 2.0f - 1.0f) * spread; };
  const Vec3 o(u(), u(), u());
  Vec3 d;
  if (spread > 2.0f) {
    d = Vec3(rng.uniform() * 2 - 1, rng.uniform() * 2 - 1, rng.uniform() * 2 - 1) - o;
  } else {
    do {
      d = Vec3(rng.uniform() * 2 - 1, rng.uniform() * 2 - 1, rng.uniform() * 2 - 1);
    } while (norm2(d) > 1 || norm2(d) < 1e-6f);
  }
  const float kind = rng.uniform();
  if (kind < 0.1f) d.x = 0;  // axis-parallel components
  if (kind >= 0.1f && kind < 0.2f) d.y = d.z = 0;
  if (norm2(d) == 0) d = Vec3(0, 0, 1);
  return Ray(o, normalize(d), 0.0f, 1e30f);
}

// Compares closest hits and occlusion of the BVH with brute force.
void check_equivalence(const Scene& scene, const BVH& bvh, int rays, uint64_t seed, float spread) {
  BruteForceIntersector brute(scene);
  Rng rng(seed);
  int hits = 0, mismatches = 0;
  for (int i = 0; i < rays; ++i) {
    const Ray ray = random_ray(rng, spread);
    Ray a = ray, b = ray;
    Hit ha, hb;
    const bool fa = brute.intersect(a, &ha);
    const bool fb = bvh.intersect(b, &hb);
    bool same = fa == fb;
    if (same && fa) {
      hits++;
      // The same t. Overlapping coplanar primitives tie, so another
      // primitive at that distance is a correct answer too; the same
      // primitive must give the same normal.
      same = std::abs(ha.t - hb.t) <= 1e-5f * std::max(1.0f, ha.t);
      if (same && ha.primitive == hb.primitive) same = ha.n == hb.n && ha.material == hb.material;
    }
    // Occlusion agrees with the closest hit, on the full and on a shortened ray.
    same = same && bvh.occluded(ray) == fa;
    if (fa) {
      Ray before = ray;
      before.max_t = ha.t * 0.999f;
      Ray probe = before;
      Hit ignored;
      const bool nearer = brute.intersect(probe, &ignored);
      same = same && bvh.occluded(before) == nearer;
    }
    if (!same) {
      ++mismatches;
      if (mismatches <= 5) {
        INFO("ray " << i << ": o " << ray.o.x << " " << ray.o.y << " " << ray.o.z << " d " << ray.d.x << " "
                    << ray.d.y << " " << ray.d.z << " brute " << fa << " t " << ha.t << " prim " << ha.primitive
                    << " bvh " << fb << " t " << hb.t << " prim " << hb.primitive);
        CHECK(same);
      }
    }
  }
  CHECK(mismatches == 0);
  CHECK(hits > rays / 20);  // the test exercised hits, not just misses
}

}  // namespace

TEST_CASE("BVH bounds and statistics on a random triangle and sphere soup, for several leaf sizes", "[part2][bvh]") {
  const Scene s = random_scene(5000, 40, 1);
  for (int leaf : {1, 2, 4, 8}) {
    INFO("max leaf " << leaf);
    BVHOptions o;
    o.max_leaf_size = leaf;
    const BVH bvh(s, o);
    check_interface(s, bvh, leaf);
    CHECK(bvh.build_stats().depth < 64);
    // BEGIN SOLUTION
    check_reference_layout(s, bvh, leaf);
    // END SOLUTION
  }
}

TEST_CASE("BVH closest hit and occlusion equal brute force on 100k random rays", "[part2][bvh]") {
  const Scene s = random_scene(3000, 30, 2);
  const BVH bvh(s);
  check_equivalence(s, bvh, 100000, 7, 1.5f);
}

TEST_CASE("BVH equals brute force on rays starting inside boxes and far outside", "[part2][bvh]") {
  const Scene s = random_scene(2000, 10, 3);
  const BVH bvh(s);
  check_equivalence(s, bvh, 30000, 8, 0.3f);   // origins deep inside the tree
  check_equivalence(s, bvh, 30000, 9, 10.0f);  // from outside the root box, aimed into it
}

TEST_CASE("BVH equals brute force on a course scene", "[part2][bvh][course]") {
  const Scene s = load_collada(test::course_scene("CBbunny.dae"));
  const BVH bvh(s);
  check_interface(s, bvh, 4);
  // BEGIN SOLUTION
  check_reference_layout(s, bvh, 4);
  // END SOLUTION
  check_equivalence(s, bvh, 5000, 11, 1.0f);  // brute force on 28k triangles is slow
}

TEST_CASE("BVH degenerate input: one centroid, one triangle, zero-area triangles, empty scene", "[part2][bvh]") {
  SECTION("all primitives share one centroid") {
    Scene s;
    s.materials.push_back(Material{});
    // Nested triangles of growing size in the plane y = 0, some tilted.
    for (int i = 0; i < 200; ++i) {
      const float a = 0.01f * float(i + 1), tilt = (i % 3) * 0.3f * a;
      s.triangles.push_back(make_triangle({-a, -tilt, -a}, {a, tilt, -a}, {0, 0, 2 * a}));
    }
    for (auto& t : s.triangles) {  // shift each so that its box centre is the origin
      const Vec3 c = t.bounds().centroid();
      t.p1 -= c;
      t.p2 -= c;
      t.p3 -= c;
    }
    const BVH bvh(s);
    check_interface(s, bvh, 4);
    // BEGIN SOLUTION
    check_reference_layout(s, bvh, 4);
    // END SOLUTION
    check_equivalence(s, bvh, 5000, 12, 3.0f);
  }
  SECTION("a single triangle") {
    Scene s;
    s.materials.push_back(Material{});
    s.triangles.push_back(make_triangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0}));
    const BVH bvh(s);
    check_interface(s, bvh, 4);
    // BEGIN SOLUTION
    check_reference_layout(s, bvh, 4);
    // END SOLUTION
    CHECK(bvh.build_stats().nodes == 1);
    Ray r({0.2f, 0.2f, 1}, {0, 0, -1});
    Hit h;
    REQUIRE(bvh.intersect(r, &h));
    CHECK(h.t == Approx(1.0f));
    CHECK(h.primitive == 0);
  }
  SECTION("zero-area triangles never hit and do not break the build") {
    Scene s = random_scene(500, 0, 4);
    for (int i = 0; i < 100; ++i) {
      const Vec3 p(0.01f * i, 0, 0);
      s.triangles.push_back(make_triangle(p, p, p + Vec3(1, 0, 0)));  // collinear: zero area
      s.triangles.back().n1 = s.triangles.back().n2 = s.triangles.back().n3 = Vec3(0, 0, 1);
    }
    const BVH bvh(s);
    check_interface(s, bvh, 4);
    // BEGIN SOLUTION
    check_reference_layout(s, bvh, 4);
    // END SOLUTION
    check_equivalence(s, bvh, 5000, 13, 1.5f);
  }
  SECTION("an empty scene") {
    Scene s;
    const BVH bvh(s);
    CHECK(bvh.build_stats().nodes == 0);
    CHECK(bvh.bounds().empty());
    Ray r({0, 0, 0}, {0, 0, 1});
    Hit h;
    CHECK_FALSE(bvh.intersect(r, &h));
    CHECK_FALSE(bvh.occluded(r));
  }
}

TEST_CASE("BVH counters: one query per call, and fewer tests than brute force", "[part2][bvh]") {
  const Scene s = random_scene(4000, 0, 5);
  const BVH bvh(s);
  RayStats& st = thread_ray_stats();
  st = RayStats{};
  Rng rng(3);
  for (int i = 0; i < 1000; ++i) {
    Ray r = random_ray(rng, 1.0f);
    Hit h;
    bvh.intersect(r, &h);
    bvh.occluded(random_ray(rng, 1.0f));
  }
  CHECK(st.closest_queries == 1000u);
  CHECK(st.shadow_queries == 1000u);
  CHECK(st.node_visits > 0u);
  CHECK(st.primitive_tests < 2000u * 4000u / 20);  // at least 20x fewer than testing everything
}

TEST_CASE("BVH build: the same tree for any number of build threads", "[part2][bvh]") {
  // Large enough for a parallel builder to split its work.
  const Scene s = random_scene(60000, 20, 6);
  std::vector<RayStats> counts;
  std::vector<BVHBuildStats> builds;
  std::vector<std::vector<float>> hits;
  for (int threads : {1, 2, 3, 8}) {
    BVHOptions o;
    o.build_threads = threads;
    const BVH bvh(s, o);
    builds.push_back(bvh.build_stats());
    RayStats& st = thread_ray_stats();
    st = RayStats{};
    Rng rng(21);
    std::vector<float> t;
    for (int i = 0; i < 2000; ++i) {
      Ray r = random_ray(rng, 1.5f);
      Hit h;
      t.push_back(bvh.intersect(r, &h) ? h.t + float(h.primitive) : -1.0f);
      t.push_back(bvh.occluded(random_ray(rng, 1.5f)) ? 1.0f : 0.0f);
    }
    counts.push_back(st);
    hits.push_back(t);
  }
  for (size_t k = 1; k < builds.size(); ++k) {
    INFO("thread count #" << k);
    CHECK(builds[k].nodes == builds[0].nodes);
    CHECK(builds[k].leaves == builds[0].leaves);
    CHECK(builds[k].depth == builds[0].depth);
    CHECK(builds[k].sah_cost == builds[0].sah_cost);
    CHECK(counts[k].primitive_tests == counts[0].primitive_tests);
    CHECK(counts[k].node_visits == counts[0].node_visits);
    CHECK(hits[k] == hits[0]);
  }
}
