// Tests of the primitive readers (<polylist>, <triangles>, <polygons>) and
// of the position arrays they index.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "tests/common/collada_documents.h"

using Catch::Matchers::Contains;
using namespace pt::test::dae;

TEST_CASE("polylist polygons are fan-triangulated, all vertices read", "[collada]") {
  // A unit quad (0..3) and a pentagon (4..8) in the plane z = 0.
  const std::vector<double> xyz = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0,                        // quad
                                   3, 0, 0, 4, 0, 0, 4.5, 1, 0, 3.5, 2, 0, 2.5, 1, 0};       // pentagon
  Doc d;
  d.geometries = mesh("g", xyz, polylist("g", "4 5", "0 1 2 3 4 5 6 7 8"));
  d.nodes = node("", instance_geometry("g"));
  const Loaded l = load(d);
  REQUIRE(l.scene.triangles.size() == 2 + 3);
  const auto& t = l.scene.triangles;
  // Fan from the first vertex: (v0, v1, v2), (v0, v2, v3), ...
  check_vec(t[0].p1, 0, 0, 0); check_vec(t[0].p2, 1, 0, 0); check_vec(t[0].p3, 1, 1, 0);
  check_vec(t[1].p1, 0, 0, 0); check_vec(t[1].p2, 1, 1, 0); check_vec(t[1].p3, 0, 1, 0);
  check_vec(t[2].p1, 3, 0, 0); check_vec(t[2].p2, 4, 0, 0); check_vec(t[2].p3, 4.5, 1, 0);
  check_vec(t[4].p1, 3, 0, 0); check_vec(t[4].p2, 3.5, 2, 0); check_vec(t[4].p3, 2.5, 1, 0);
  CHECK(l.warnings.size() == 1);  // only "no camera"
}

TEST_CASE("inputs with offsets: the VERTEX index is picked out of each vertex's indices", "[collada]") {
  const std::string normals =
      "<source id=\"g-normals\"><float_array id=\"g-normals-array\" count=\"6\">0 0 1 0 0 -1</float_array>"
      "<technique_common><accessor source=\"#g-normals-array\" count=\"2\" stride=\"3\"/></technique_common>"
      "</source>";
  const std::string prim = "<polylist count=\"1\">" + vertex_input("g") +
                           "<input semantic=\"NORMAL\" source=\"#g-normals\" offset=\"1\"/>"
                           "<vcount>3</vcount><p>2 1 0 0 1 1</p></polylist>";
  Doc d;
  d.geometries = mesh("g", "0 0 0 1 0 0 0 1 0", 3, prim, normals);
  d.nodes = node("", instance_geometry("g"));
  const Loaded l = load(d);
  REQUIRE(l.scene.triangles.size() == 1);
  check_vec(l.scene.triangles[0].p1, 0, 1, 0);
  check_vec(l.scene.triangles[0].p2, 0, 0, 0);
  check_vec(l.scene.triangles[0].p3, 1, 0, 0);
  // The file's normals (0,0,-1) for two vertices are ignored: recomputed
  // (reversed from the winding's (0,0,1): a lone triangle is all boundary).
  check_vec(l.scene.triangles[0].n1, 0, 0, -1);
  check_vec(l.scene.triangles[0].n2, 0, 0, -1);
}

TEST_CASE("<triangles> and <polygons> are read", "[collada]") {
  const std::vector<double> quad = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  SECTION("triangles") {
    Doc d;
    d.geometries = mesh("g", quad, triangles("g", 2, "0 1 2  0 2 3"));
    d.nodes = node("", instance_geometry("g"));
    const Loaded l = load(d);
    REQUIRE(l.scene.triangles.size() == 2);
    check_vec(l.scene.triangles[1].p3, 0, 1, 0);
  }
  SECTION("polygons: one <p> per polygon") {
    Doc d;
    d.geometries =
        mesh("g", quad, "<polygons count=\"2\">" + vertex_input("g") + "<p>0 1 2 3</p><p>0 1 2</p></polygons>");
    d.nodes = node("", instance_geometry("g"));
    const Loaded l = load(d);
    CHECK(l.scene.triangles.size() == 3);
  }
}

TEST_CASE("every primitive list of a mesh is read, each with its own material", "[collada][materials]") {
  const std::vector<double> xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0, 5, 0, 0, 6, 0, 0, 5, 1, 0};
  Doc d;
  d.effects = effect_common("red-fx", "lambert", "1 0 0 1") + effect_common("blue-fx", "phong", "0 0 1 1");
  d.materials = material("red", "red-fx") + material("blue", "blue-fx");
  d.geometries = mesh("g", xyz, polylist("g", "3", "0 1 2", "sym-red") + triangles("g", 1, "3 4 5", "sym-blue"));
  d.nodes = node("", instance_geometry("g", {{"sym-blue", "blue"}, {"sym-red", "red"}}));
  const Loaded l = load(d);
  REQUIRE(l.scene.triangles.size() == 2);
  const auto& m = l.scene.materials;
  const pt::Material& m0 = m.at(size_t(l.scene.triangles[0].material));
  const pt::Material& m1 = m.at(size_t(l.scene.triangles[1].material));
  CHECK(m0.name == "red");
  check_vec(m0.albedo, 1, 0, 0);
  CHECK(m1.name == "blue");
  check_vec(m1.albedo, 0, 0, 1);
  CHECK(l.scene.triangles[1].p1.x == Approx(5));
  CHECK(m.size() == 2);
}

TEST_CASE("unsupported primitive lists are skipped with a warning", "[collada]") {
  const std::vector<std::string> kinds = {"lines", "linestrips", "tristrips", "trifans"};
  for (const std::string& kind : kinds) {
    SECTION(kind) {
      Doc d;
      d.geometries = mesh("g", {0, 0, 0, 1, 0, 0, 0, 1, 0},
                          "<" + kind + " count=\"1\">" + vertex_input("g") + "<p>0 1 2</p></" + kind + ">" +
                              polylist("g", "3", "0 1 2"));
      d.nodes = node("", instance_geometry("g"));
      const Loaded l = load(d);
      CHECK(l.scene.triangles.size() == 1);
      CHECK(has_warning(l, "<" + kind + ">", "not supported"));
    }
  }
}

// ---- Bad input -------------------------------------------------------------------

TEST_CASE("bad number arrays are errors naming the array", "[collada][errors]") {
  Doc d;
  d.nodes = node("", instance_geometry("g"));
  const std::string array = "<float_array id=\"g-positions-array\">";
  SECTION("fewer numbers than count") {
    d.geometries = mesh("g", "0 0 0 1 0 0 0 1", 3, polylist("g", "3", "0 1 2"));
    CHECK_THAT(error_of(d), Contains(array) && Contains("count=\"9\"") && Contains("8 numbers"));
  }
  SECTION("a token that is not a number") {
    d.geometries = mesh("g", "0 0 0 1 0 0 0 1 zero", 3, polylist("g", "3", "0 1 2"));
    CHECK_THAT(error_of(d), Contains(array) && Contains("'zero'"));
  }
  SECTION("NaN coordinate") {
    d.geometries = mesh("g", "0 0 0 1 nan 0 0 1 0", 3, polylist("g", "3", "0 1 2"));
    CHECK_THAT(error_of(d), Contains(array) && Contains("position 1") && Contains("not finite"));
  }
  SECTION("infinite coordinate") {
    d.geometries = mesh("g", "0 0 0 1 0 0 0 -INF 0", 3, polylist("g", "3", "0 1 2"));
    CHECK_THAT(error_of(d), Contains(array) && Contains("position 2") && Contains("not finite"));
  }
  SECTION("coordinate beyond the range of double") {
    d.geometries = mesh("g", "0 0 0 1 0 0 0 1e999 0", 3, polylist("g", "3", "0 1 2"));
    CHECK_THAT(error_of(d), Contains(array) && Contains("position 2") && Contains("not finite"));
  }
  SECTION("coordinate that overflows float after the transform") {
    d.geometries = mesh("g", "0 0 0 1 0 0 0 1e30 0", 3, polylist("g", "3", "0 1 2"));
    d.nodes = node("<scale>1e10 1e10 1e10</scale>", instance_geometry("g"));
    CHECK_THAT(error_of(d), Contains(array) && Contains("position 2") && Contains("not finite"));
  }
  SECTION("accessor reading past the array") {
    d.geometries = mesh("g", "0 0 0 1 0 0 0 1 0", 3, polylist("g", "3", "0 1 2"));
    const std::string doc = d.str();
    std::string bad = doc;
    bad.replace(bad.find("count=\"3\" stride"), 9, "count=\"4\"");
    CHECK_THAT(error_of(bad), Contains("<accessor>") && Contains("past the end"));
  }
}

TEST_CASE("bad primitive lists are errors naming the element", "[collada][errors]") {
  Doc d;
  d.nodes = node("", instance_geometry("g"));
  const std::vector<double> quad = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  SECTION("index out of range") {
    d.geometries = mesh("g", quad, polylist("g", "3", "0 1 4"));
    CHECK_THAT(error_of(d), Contains("<p>") && Contains("index 4") && Contains("out of range") &&
                                Contains("<source id=\"g-positions\">"));
  }
  SECTION("negative index") {
    d.geometries = mesh("g", quad, triangles("g", 1, "0 -1 2"));
    CHECK_THAT(error_of(d), Contains("<p>") && Contains("index -1"));
  }
  SECTION("index out of range of a non-position source") {
    const std::string normals =
        "<source id=\"g-normals\"><float_array id=\"g-normals-array\" count=\"3\">0 0 1</float_array>"
        "<technique_common><accessor source=\"#g-normals-array\" count=\"1\" stride=\"3\"/></technique_common>"
        "</source>";
    d.geometries = mesh("g", "0 0 0 1 0 0 0 1 0", 3,
                        "<triangles count=\"1\">" + vertex_input("g") +
                            "<input semantic=\"NORMAL\" source=\"#g-normals\" offset=\"1\"/>"
                            "<p>0 0 1 0 2 1</p></triangles>",
                        normals);
    CHECK_THAT(error_of(d), Contains("index 1") && Contains("<source id=\"g-normals\">"));
  }
  SECTION("<p> shorter than <vcount> demands") {
    d.geometries = mesh("g", quad, polylist("g", "3 3", "0 1 2 0 2"));
    CHECK_THAT(error_of(d), Contains("<p>") && Contains("5 indices") && Contains("needs 6"));
  }
  SECTION("a polygon with fewer than 3 vertices") {
    d.geometries = mesh("g", quad, polylist("g", "3 2", "0 1 2 0 2"));
    CHECK_THAT(error_of(d), Contains("<vcount>") && Contains("polygon 1 has 2 vertices"));
  }
  SECTION("a non-integer index") {
    d.geometries = mesh("g", quad, polylist("g", "3", "0 1 2.5"));
    CHECK_THAT(error_of(d), Contains("<p>") && Contains("'2.5'"));
  }
  SECTION("<triangles> with a partial triangle") {
    d.geometries = mesh("g", quad, triangles("g", 2, "0 1 2 0 2"));
    CHECK_THAT(error_of(d), Contains("<p>") && Contains("5 indices"));
  }
  SECTION("<polygons> with a two-vertex polygon") {
    d.geometries = mesh("g", quad, "<polygons count=\"1\">" + vertex_input("g") + "<p>0 1</p></polygons>");
    CHECK_THAT(error_of(d), Contains("<p>") && Contains("2 vertices"));
  }
  SECTION("no VERTEX input") {
    d.geometries = mesh("g", quad, "<triangles count=\"1\"><p>0 1 2</p></triangles>");
    CHECK_THAT(error_of(d), Contains("<triangles>") && Contains("VERTEX"));
  }
}
