// Part 1, tasks 3 and 4: ray-triangle and ray-sphere intersection.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "stages/part1_raytracing/sphere.h"
#include "stages/part1_raytracing/triangle.h"

using namespace pt;

namespace {
Triangle unit_triangle() {
  // In the z = 0 plane, normals all +Z unless a test changes them.
  Triangle t;
  t.p1 = {0, 0, 0};
  t.p2 = {1, 0, 0};
  t.p3 = {0, 1, 0};
  t.n1 = t.n2 = t.n3 = {0, 0, 1};
  t.material = 3;
  return t;
}
Ray down_at(float x, float y) { return Ray({x, y, 1}, {0, 0, -1}, 0.0f, 100.0f); }
}  // namespace

TEST_CASE("triangle: a ray through the interior hits and shrinks max_t", "[part1][triangle]") {
  Triangle t = unit_triangle();
  Ray r = down_at(0.25f, 0.25f);
  Hit h;
  REQUIRE(intersect_triangle(t, r, &h));
  CHECK(h.t == Approx(1.0f));
  CHECK(r.max_t == Approx(1.0f));
  CHECK(h.material == 3);
  CHECK(h.n == Vec3(0, 0, 1));
}

TEST_CASE("triangle: misses outside, parallel rays, and hits outside the ray interval", "[part1][triangle]") {
  const Triangle t = unit_triangle();
  Hit h;
  Ray out = down_at(0.75f, 0.75f);  // beyond the hypotenuse
  CHECK_FALSE(intersect_triangle(t, out, &h));
  CHECK(out.max_t == 100.0f);  // untouched on a miss
  Ray neg = down_at(-0.1f, 0.5f);
  CHECK_FALSE(intersect_triangle(t, neg, &h));
  Ray parallel({0.2f, 0.2f, 0}, {1, 0, 0}, 0.0f, 100.0f);  // in the plane
  CHECK_FALSE(intersect_triangle(t, parallel, &h));
  Ray above({0.2f, 0.2f, 1}, {1, 0, 0}, 0.0f, 100.0f);
  CHECK_FALSE(intersect_triangle(t, above, &h));
  Ray too_far = down_at(0.25f, 0.25f);
  too_far.max_t = 0.5f;
  CHECK_FALSE(intersect_triangle(t, too_far, &h));
  Ray too_near = down_at(0.25f, 0.25f);
  too_near.min_t = 1.5f;
  CHECK_FALSE(intersect_triangle(t, too_near, &h));
  Ray behind({0.25f, 0.25f, -1}, {0, 0, -1}, 0.0f, 100.0f);  // triangle behind the origin
  CHECK_FALSE(intersect_triangle(t, behind, &h));
}

TEST_CASE("triangle: edges and vertices count as hits, from either side", "[part1][triangle]") {
  const Triangle t = unit_triangle();
  for (auto [x, y] : {std::pair{0.5f, 0.0f}, {0.0f, 0.5f}, {0.5f, 0.5f}, {0.0f, 0.0f}, {1.0f, 0.0f}}) {
    Ray r = down_at(x, y);
    INFO("edge point " << x << ", " << y
                       << ". Hint: on an edge or at a vertex a barycentric coordinate is exactly 0 (or b1 + b2 "
                          "exactly 1): accept it (b1 >= 0, b2 >= 0, b1 + b2 <= 1), so that no ray slips between "
                          "two triangles that share the edge.");
    CHECK(intersect_triangle(t, r, nullptr));
  }
  Ray from_below({0.2f, 0.2f, -2}, {0, 0, 1}, 0.0f, 100.0f);
  Hit h;
  REQUIRE(intersect_triangle(t, from_below, &h));
  CHECK(h.t == Approx(2.0f));
}

TEST_CASE("triangle: the normal is interpolated with barycentric weights", "[part1][triangle]") {
  Triangle t = unit_triangle();
  t.n1 = {0, 0, 1};
  t.n2 = {1, 0, 0};
  t.n3 = {0, 1, 0};
  Hit h;
  Ray at_p2 = down_at(1.0f, 0.0f);
  INFO("a ray through the vertex p2 must hit (see the test of edges and vertices)");
  REQUIRE(intersect_triangle(t, at_p2, &h));
  CHECK(h.n.x == Approx(1.0f));
  // At (0.5, 0.25): weights 0.25 (p1), 0.5 (p2), 0.25 (p3).
  Ray mid = down_at(0.5f, 0.25f);
  REQUIRE(intersect_triangle(t, mid, &h));
  const Vec3 e = normalize(Vec3(0.5f, 0.25f, 0.25f));
  CHECK(h.n.x == Approx(e.x));
  CHECK(h.n.y == Approx(e.y));
  CHECK(h.n.z == Approx(e.z));
  CHECK(norm(h.n) == Approx(1.0f));
}

TEST_CASE("triangle: the nearer of two triangles wins through max_t", "[part1][triangle]") {
  Triangle near_t = unit_triangle(), far_t = unit_triangle();
  for (Vec3* p : {&far_t.p1, &far_t.p2, &far_t.p3}) p->z = -3;
  far_t.material = 9;
  Ray r = down_at(0.2f, 0.2f);
  Hit h;
  CHECK(intersect_triangle(far_t, r, &h));
  CHECK(intersect_triangle(near_t, r, &h));
  CHECK(h.material == 3);
  // Tested in the other order the far one must now be rejected.
  Ray r2 = down_at(0.2f, 0.2f);
  CHECK(intersect_triangle(near_t, r2, &h));
  CHECK_FALSE(intersect_triangle(far_t, r2, &h));
  CHECK(h.material == 3);
}

TEST_CASE("sphere: hit from outside returns the nearer root and outward normal", "[part1][sphere]") {
  Sphere s{{0, 0, -5}, 1.0f, 2};
  Ray r({0, 0, 0}, {0, 0, -1}, 0.0f, 100.0f);
  Hit h;
  REQUIRE(intersect_sphere(s, r, &h));
  CHECK(h.t == Approx(4.0f));
  CHECK(r.max_t == Approx(4.0f));
  CHECK(h.n.z == Approx(1.0f));
  CHECK(h.material == 2);
  // Off-centre: the normal is (p - c) / R.
  Ray off({0.6f, 0, 0}, {0, 0, -1}, 0.0f, 100.0f);
  REQUIRE(intersect_sphere(s, off, &h));
  CHECK(h.t == Approx(5.0f - 0.8f));
  CHECK(h.n.x == Approx(0.6f));
  CHECK(h.n.z == Approx(0.8f));
}

TEST_CASE("sphere: from inside, and with min_t past the near root, the far root is hit", "[part1][sphere]") {
  Sphere s{{0, 0, 0}, 2.0f, 0};
  Ray inside({0, 0, 0}, {1, 0, 0}, 0.0f, 100.0f);
  Hit h;
  REQUIRE(intersect_sphere(s, inside, &h));
  CHECK(h.t == Approx(2.0f));
  CHECK(h.n.x == Approx(1.0f));  // outward even when hit from inside
  Ray through({-5, 0, 0}, {1, 0, 0}, 3.5f, 100.0f);  // near root 3 < min_t
  REQUIRE(intersect_sphere(s, through, &h));
  CHECK(h.t == Approx(7.0f));
}

TEST_CASE("sphere: misses, behind the ray, beyond max_t, grazing", "[part1][sphere]") {
  Sphere s{{0, 0, -5}, 1.0f, 0};
  Hit h;
  Ray miss({2, 0, 0}, {0, 0, -1}, 0.0f, 100.0f);
  CHECK_FALSE(intersect_sphere(s, miss, &h));
  CHECK(miss.max_t == 100.0f);
  Ray away({0, 0, 0}, {0, 0, 1}, 0.0f, 100.0f);
  CHECK_FALSE(intersect_sphere(s, away, &h));
  Ray short_ray({0, 0, 0}, {0, 0, -1}, 0.0f, 3.0f);
  CHECK_FALSE(intersect_sphere(s, short_ray, &h));
  Ray graze({1, 0, 0}, {0, 0, -1}, 0.0f, 100.0f);  // tangent at (1, 0, -5)
  REQUIRE(intersect_sphere(s, graze, &h));
  CHECK(h.t == Approx(5.0f).margin(1e-3));
}

TEST_CASE("sphere: distant spheres keep precision", "[part1][sphere]") {
  // |o - c|^2 - R^2 cancels badly in float for far spheres.
  Sphere s{{0, 0, -1000}, 0.5f, 0};
  Ray r({0, 0, 0}, {0, 0, -1}, 0.0f, 1e6f);
  Hit h;
  INFO("Hint: |o - c|^2 - R^2 is a difference of two large, nearly equal numbers here: compute it (and the "
       "quadratic's roots) in double.");
  REQUIRE(intersect_sphere(s, r, &h));
  CHECK(h.t == Approx(999.5f).margin(1e-3));
}

TEST_CASE("sphere: a radius whose square overflows float still gives a unit normal", "[part1][sphere]") {
  // r = 2^64: r^2 = 2^128 is past FLT_MAX, so the hit point minus the centre
  // squared overflows in float arithmetic. The normal must still be unit
  // length and point outward (what the loader fuzzer found).
  const float huge = 18446744073709551616.0f;
  Sphere s{{0, 0, 0}, huge, 0};
  Ray r({0, 0, -2 * huge}, {0, 0, 1}, 1e-4f, std::numeric_limits<float>::infinity());
  Hit h;
  INFO("Hint: in float, this sphere's R^2 = 2^128 overflows to infinity, and |o - c|^2 - R^2 becomes inf - inf = "
       "NaN: no hit. Compute the quadratic's coefficients and roots in double (the course's Vector3D is double), "
       "and the normal as (p - c) normalised.");
  REQUIRE(intersect_sphere(s, r, &h));
  CHECK(h.t == Approx(huge).epsilon(1e-6));
  CHECK(std::isfinite(h.n.x));
  CHECK(h.n.z == Approx(-1.0f).margin(1e-6));
  CHECK(norm(h.n) == Approx(1.0f).margin(1e-6));
  // A ray from far away at a small sphere: the hit point's error, not the
  // radius, is what is huge there.
  Sphere small{{0, 0, 0}, 1.0f, 0};
  Ray far({3e38f, 0, 0}, {-1, 0, 0}, 0.0f, std::numeric_limits<float>::infinity());
  if (intersect_sphere(small, far, &h)) CHECK(norm(h.n) == Approx(1.0f).margin(1e-6));
}
