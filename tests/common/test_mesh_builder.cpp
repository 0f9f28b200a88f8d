// Tests of the mesh builder alone, on position indices and positions
// written in the test (no XML): renumbering, world positions, boundary
// detection, dropped zero-area triangles and smooth normals.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "common/collada/mesh_builder.h"

using pt::collada::MeshTriangles;
using pt::collada::TriangleIndices;

namespace {

std::vector<pt::Vec3> points(const std::vector<double>& xyz) {
  std::vector<pt::Vec3> p;
  for (size_t i = 0; i + 2 < xyz.size(); i += 3) p.push_back(pt::Vec3(pt::Vec3d(xyz[i], xyz[i + 1], xyz[i + 2])));
  return p;
}

MeshTriangles mesh_of(const std::vector<TriangleIndices>& corners, const std::vector<int>& materials = {}) {
  MeshTriangles m;
  m.corners = corners;
  m.materials = materials.empty() ? std::vector<int>(corners.size(), 0) : materials;
  return m;
}

void check_vec(const pt::Vec3& v, double x, double y, double z) {
  INFO("got (" << v.x << ", " << v.y << ", " << v.z << "), want (" << x << ", " << y << ", " << z << ")");
  CHECK(v.x == Approx(x).margin(1e-6));
  CHECK(v.y == Approx(y).margin(1e-6));
  CHECK(v.z == Approx(z).margin(1e-6));
}

// A tetrahedron wound so that every face's (v1-v0) x (v2-v0) points outward.
const std::vector<double> kTetrahedron = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
const std::vector<TriangleIndices> kTetrahedronFaces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};

}  // namespace

TEST_CASE("mesh builder: the used positions are renumbered in the order of their indices", "[collada][mesh]") {
  // 8 positions for 2 triangles take the dense table, 1000 the sorted list.
  for (const size_t count : {size_t(8), size_t(1000)}) {
    SECTION(std::to_string(count) + " positions in the file") {
      std::vector<TriangleIndices> tris = {{7, 2, 5}, {5, 2, 3}};
      const std::vector<int> used = pt::collada::renumber_used_positions(tris, count);
      CHECK(used == std::vector<int>{2, 3, 5, 7});
      CHECK(tris[0] == TriangleIndices{3, 0, 2});
      CHECK(tris[1] == TriangleIndices{2, 0, 1});
    }
  }
}

TEST_CASE("mesh builder: positions go to world space in float, and the first that overflows float is named",
          "[collada][mesh]") {
  const std::vector<double> xyz = {0, 0, 0, 1, 2, 3, 1e30, 0, 0, 4, 5, 6};
  std::vector<pt::Vec3> out;
  SECTION("finite: only the used positions, in the order given") {
    const auto bad = pt::collada::world_positions(xyz, {1, 3}, pt::Mat4::translate({1, 0, 0}), &out);
    CHECK_FALSE(bad.has_value());
    REQUIRE(out.size() == 2);
    check_vec(out[0], 2, 2, 3);
    check_vec(out[1], 5, 5, 6);
  }
  SECTION("beyond float's range after the transform: its index in the file and its place") {
    const auto bad = pt::collada::world_positions(xyz, {1, 2, 3}, pt::Mat4::scale({1e10, 1e10, 1e10}), &out);
    REQUIRE(bad.has_value());
    CHECK(bad->index == 2);
    CHECK(bad->point.x == Approx(1e40));
    CHECK(bad->point.y == 0);
  }
}

TEST_CASE("mesh builder: a mesh is all boundary when every vertex it uses lies on an edge of one triangle",
          "[collada][mesh]") {
  auto faces = [](size_t n) { return std::vector<pt::Vec3d>(n, pt::Vec3d(0, 0, 1)); };
  CHECK(pt::collada::all_vertices_on_boundary({{0, 1, 2}}, faces(1)));
  CHECK(pt::collada::all_vertices_on_boundary({{0, 1, 2}, {0, 2, 3}}, faces(2)));  // a quad
  CHECK_FALSE(pt::collada::all_vertices_on_boundary(kTetrahedronFaces, faces(4)));  // closed
  // A fan around the interior vertex 0.
  CHECK_FALSE(pt::collada::all_vertices_on_boundary({{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 1}}, faces(4)));
  SECTION("degenerate triangles (zero face normal) do not count") {
    // The quad again, with a zero-area copy of its first triangle: counted,
    // it would make the edges 0-1 and 1-2 interior.
    std::vector<pt::Vec3d> face = faces(3);
    face[2] = pt::Vec3d(0.0);
    CHECK(pt::collada::all_vertices_on_boundary({{0, 1, 2}, {0, 2, 3}, {0, 1, 2}}, face));
    CHECK_FALSE(pt::collada::all_vertices_on_boundary({{0, 1, 2}}, {pt::Vec3d(0.0)}));  // nothing left
  }
}

TEST_CASE("mesh builder: smooth normals are area-weighted sums, reversed for an all-boundary mesh",
          "[collada][mesh]") {
  // Face A in z=0 with cross product (0,0,4), face B in x=0 with (1,0,0);
  // they share vertex 0. Both are all boundary, so every normal is reversed.
  const std::vector<pt::Vec3> wp = points({0, 0, 0, 2, 0, 0, 0, 2, 0, 0, 1, 0, 0, 0, 1});
  std::vector<pt::Triangle> out;
  CHECK(pt::collada::add_mesh_triangles(wp, mesh_of({{0, 1, 2}, {0, 3, 4}}, {3, 5}), out) == 0);
  REQUIRE(out.size() == 2);
  const double s = 1 / std::sqrt(17.0);
  check_vec(out[0].n1, -1 * s, 0, -4 * s);
  check_vec(out[1].n1, -1 * s, 0, -4 * s);
  check_vec(out[0].n2, 0, 0, -1);  // only on face A
  check_vec(out[1].n3, -1, 0, 0);  // only on face B
  check_vec(out[1].p2, 0, 1, 0);
  CHECK(out[0].material == 3);
  CHECK(out[1].material == 5);
}

TEST_CASE("mesh builder: a closed mesh keeps its winding", "[collada][mesh]") {
  const std::vector<pt::Vec3> wp = points(kTetrahedron);
  std::vector<pt::Triangle> out;
  pt::collada::add_mesh_triangles(wp, mesh_of(kTetrahedronFaces), out);
  REQUIRE(out.size() == 4);
  const pt::Vec3 centroid(0.25f, 0.25f, 0.25f);
  for (const pt::Triangle& t : out) {
    CHECK(pt::dot(t.n1, t.p1 - centroid) > 0);
    CHECK(pt::dot(t.n2, t.p2 - centroid) > 0);
    CHECK(pt::dot(t.n3, t.p3 - centroid) > 0);
  }
}

TEST_CASE("mesh builder: zero-area triangles are dropped and counted, the rest appended", "[collada][mesh]") {
  // Triangle 0 is fine, 1 repeats an index, 2 is collinear.
  const std::vector<pt::Vec3> wp = points({0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0});
  std::vector<pt::Triangle> out(1);
  out[0].material = 42;
  CHECK(pt::collada::add_mesh_triangles(wp, mesh_of({{0, 1, 2}, {0, 1, 1}, {0, 1, 3}}, {7, 8, 9}), out) == 2);
  REQUIRE(out.size() == 2);
  CHECK(out[0].material == 42);  // what was there stays
  CHECK(out[1].material == 7);
  check_vec(out[1].p3, 0, 1, 0);
  check_vec(out[1].n1, 0, 0, -1);  // the survivor is all boundary: reversed
}

TEST_CASE("mesh builder: vertex normals that cancel fall back to the face normal", "[collada][mesh]") {
  // The same triangle wound both ways: every edge has two triangles (so the
  // winding is kept) and every vertex's sum is zero.
  const std::vector<pt::Vec3> wp = points({0, 0, 0, 1, 0, 0, 0, 1, 0});
  std::vector<pt::Triangle> out;
  pt::collada::add_mesh_triangles(wp, mesh_of({{0, 1, 2}, {0, 2, 1}}), out);
  REQUIRE(out.size() == 2);
  for (const pt::Vec3& n : {out[0].n1, out[0].n2, out[0].n3}) check_vec(n, 0, 0, 1);
  for (const pt::Vec3& n : {out[1].n1, out[1].n2, out[1].n3}) check_vec(n, 0, 0, -1);
}
