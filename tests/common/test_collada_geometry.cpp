// Tests of geometry as the loader builds it from a file: meshes
// (degenerate triangles, recomputed normals) and CGL spheres. The mesh
// builder alone is tested in test_mesh_builder.cpp.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "tests/common/collada_documents.h"

using Catch::Matchers::Contains;
using namespace pt::test::dae;

// ---- Meshes ----------------------------------------------------------------------

TEST_CASE("degenerate triangles are dropped with one warning per mesh", "[collada]") {
  // Triangle 0 is fine, 1 repeats an index, 2 is collinear.
  const std::vector<double> xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0};
  Doc d;
  d.geometries = mesh("g", xyz, polylist("g", "3 3 3", "0 1 2  0 1 1  0 1 3"));
  d.nodes = node("", instance_geometry("g"));
  const Loaded l = load(d);
  REQUIRE(l.scene.triangles.size() == 1);
  check_vec(l.scene.triangles[0].p3, 0, 1, 0);
  CHECK(has_warning(l, "<geometry id=\"g\">", "dropped 2 degenerate"));
  // The dropped triangles do not disturb the normals of the others (the
  // survivor is all boundary, so its winding normal (0,0,1) is reversed).
  check_vec(l.scene.triangles[0].n1, 0, 0, -1);
}

TEST_CASE("non-manifold meshes are accepted", "[collada]") {
  // Three triangles share the edge (0,1): a fin, not a 2-manifold.
  const std::vector<double> xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1};
  Doc d;
  d.geometries = mesh("g", xyz, polylist("g", "3 3 3", "0 1 2  1 0 3  0 1 4"));
  d.nodes = node("", instance_geometry("g"));
  CHECK(load(d).scene.triangles.size() == 3);
}

// ---- Normals ---------------------------------------------------------------------

TEST_CASE("recomputed normals: a quad (all vertices on its boundary) is reversed, as in the course",
          "[collada][normals]") {
  // Winding (v1-v0) x (v2-v0) = (0,6,0) faces +Y; the course's half-edge
  // code reverses it for meshes without interior vertices.
  Doc d;
  d.geometries = mesh("g", {0, 0, 0, 2, 0, 0, 2, 0, -3, 0, 0, -3}, polylist("g", "4", "0 1 2 3"));
  d.nodes = node("", instance_geometry("g"));
  const Loaded l = load(d);
  REQUIRE(l.scene.triangles.size() == 2);
  for (const pt::Triangle& t : l.scene.triangles) {
    check_vec(t.n1, 0, -1, 0);
    check_vec(t.n2, 0, -1, 0);
    check_vec(t.n3, 0, -1, 0);
  }
}

TEST_CASE("recomputed normals: closed meshes and open meshes with interior vertices keep their winding",
          "[collada][normals]") {
  SECTION("a closed tetrahedron wound outward has outward normals") {
    // Faces wound so that (v1-v0) x (v2-v0) points away from the centroid.
    const std::vector<double> xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    Doc d;
    d.geometries = mesh("g", xyz, polylist("g", "3 3 3 3", "0 2 1  0 1 3  0 3 2  1 2 3"));
    d.nodes = node("", instance_geometry("g"));
    const Loaded l = load(d);
    REQUIRE(l.scene.triangles.size() == 4);
    const pt::Vec3 centroid(0.25f, 0.25f, 0.25f);
    for (const pt::Triangle& t : l.scene.triangles) {
      CHECK(pt::dot(t.n1, t.p1 - centroid) > 0);
      CHECK(pt::dot(t.n2, t.p2 - centroid) > 0);
      CHECK(pt::dot(t.n3, t.p3 - centroid) > 0);
    }
  }
  SECTION("a flat fan around an interior vertex faces its winding, +Z") {
    // Centre vertex 0 surrounded by a square ring 1..4: four triangles.
    const std::vector<double> xyz = {0, 0, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0, -1, -1, 0};
    Doc d;
    d.geometries = mesh("g", xyz, polylist("g", "3 3 3 3", "0 1 2  0 2 3  0 3 4  0 4 1"));
    d.nodes = node("", instance_geometry("g"));
    const Loaded l = load(d);
    REQUIRE(l.scene.triangles.size() == 4);
    for (const pt::Triangle& t : l.scene.triangles) {
      check_vec(t.n1, 0, 0, 1);
      check_vec(t.n2, 0, 0, 1);
      check_vec(t.n3, 0, 0, 1);
    }
  }
}

TEST_CASE("recomputed normals are area-weighted sums over a shared vertex, in world space",
          "[collada][normals]") {
  // Face A in z=0 with cross product (0,0,4); face B in x=0 with cross
  // product (1,0,0) before and (3,0,0) after the scale of z by 3.
  const std::vector<double> xyz = {0, 0, 0, 2, 0, 0, 0, 2, 0, 0, 1, 0, 0, 0, 1};
  Doc d;
  d.geometries = mesh("g", xyz, polylist("g", "3 3", "0 1 2  0 3 4"));
  SECTION("untransformed") {
    d.nodes = node("", instance_geometry("g"));
    const Loaded l = load(d);
    REQUIRE(l.scene.triangles.size() == 2);
    // Both faces are all boundary, so every normal is reversed.
    const double s = 1 / std::sqrt(17.0);
    check_vec(l.scene.triangles[0].n1, -1 * s, 0, -4 * s);
    check_vec(l.scene.triangles[1].n1, -1 * s, 0, -4 * s);
    check_vec(l.scene.triangles[0].n2, 0, 0, -1);  // only on face A
    check_vec(l.scene.triangles[1].n3, -1, 0, 0);  // only on face B
  }
  SECTION("after a non-uniform scale") {
    d.nodes = node("<scale>1 1 3</scale>", instance_geometry("g"));
    const Loaded l = load(d);
    REQUIRE(l.scene.triangles.size() == 2);
    check_vec(l.scene.triangles[0].n1, -0.6, 0, -0.8);
  }
  SECTION("smoothing is per mesh instance: two instances do not share normals") {
    d.nodes = node("", instance_geometry("g")) + node("<translate>0 0 0</translate>", instance_geometry("g"));
    const Loaded l = load(d);
    REQUIRE(l.scene.triangles.size() == 4);
    const double s = 1 / std::sqrt(17.0);
    check_vec(l.scene.triangles[2].n1, -1 * s, 0, -4 * s);
  }
}

// ---- Spheres ---------------------------------------------------------------------

TEST_CASE("CGL sphere: centre and radius follow the node transform", "[collada]") {
  Doc d;
  d.geometries = "<geometry id=\"ball\"><extra><technique profile=\"CGL\"><sphere><radius>.5</radius></sphere>"
                 "</technique></extra></geometry>";
  d.effects = effect_cgl("fx", "<mirror><reflectance>1 1 1</reflectance></mirror>");
  d.materials = material("chrome", "fx");
  SECTION("Y_UP with translate and scale") {
    d.nodes = node("<translate>1 2 3</translate><scale>2 2 2</scale>", instance_geometry("ball", {{"c", "chrome"}}));
    const Loaded l = load(d);
    REQUIRE(l.scene.spheres.size() == 1);
    check_vec(l.scene.spheres[0].center, 1, 2, 3);
    CHECK(l.scene.spheres[0].radius == Approx(1.0));
    CHECK(l.scene.materials.at(size_t(l.scene.spheres[0].material)).type == pt::MaterialType::Mirror);
    CHECK(l.scene.triangles.empty());
  }
  SECTION("Z_UP matrix as the course files write it") {
    d.up_axis = "Z_UP";
    d.nodes = node("<matrix>1 0 0 -0.4 0 1 0 0.3 0 0 1 0.3 0 0 0 1</matrix>", instance_geometry("ball"));
    const Loaded l = load(d);
    REQUIRE(l.scene.spheres.size() == 1);
    check_vec(l.scene.spheres[0].center, 0.4, 0.3, 0.3);
    CHECK(l.scene.spheres[0].radius == Approx(0.5));
    CHECK(l.scene.materials.at(size_t(l.scene.spheres[0].material)).name == "default");
  }
}

TEST_CASE("a sphere needs a positive finite radius", "[collada][errors]") {
  for (const std::string r : {"0", "-1", "inf", "nan", "1 2", ""}) {
    SECTION("radius '" + r + "'") {
      Doc d;
      d.geometries = "<geometry id=\"ball\"><extra><technique profile=\"CGL\"><sphere><radius>" + r +
                     "</radius></sphere></technique></extra></geometry>";
      d.nodes = node("", instance_geometry("ball"));
      CHECK_THAT(error_of(d), Contains("<radius>"));
    }
  }
  SECTION("scaled to zero by the node") {
    Doc d;
    d.geometries = "<geometry id=\"ball\"><extra><technique profile=\"CGL\"><sphere><radius>1</radius></sphere>"
                   "</technique></extra></geometry>";
    d.nodes = node("<scale>0 0 0</scale>", instance_geometry("ball"));
    CHECK_THAT(error_of(d), Contains("degenerate"));
  }
}
