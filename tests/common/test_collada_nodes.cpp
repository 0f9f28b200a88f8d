// Tests of the node walk: transforms and their order, nested and instanced
// nodes, and the guards against cycles and exponential instancing.
#include <sys/resource.h>

#include <catch2/catch.hpp>

#include <string>
#include <utility>
#include <vector>

#include "tests/common/collada_documents.h"

using Catch::Matchers::Contains;
using namespace pt::test::dae;

// ---- Transforms ------------------------------------------------------------------

TEST_CASE("translate/rotate/scale give the same vertices as the equivalent matrix", "[collada]") {
  // T(1,2,3) * Rz(90) * S(2): x -> (1 - 2y, 2 + 2x, 3 + 2z).
  const std::string trs = "<translate>1 2 3</translate><rotate>0 0 1 90</rotate><scale>2 2 2</scale>";
  const std::string mat = "<matrix>0 -2 0 1  2 0 0 2  0 0 2 3  0 0 0 1</matrix>";
  const Loaded a = load(triangle_doc(trs));
  const Loaded b = load(triangle_doc(mat));
  REQUIRE(a.scene.triangles.size() == 1);
  REQUIRE(b.scene.triangles.size() == 1);
  const pt::Triangle &ta = a.scene.triangles[0], &tb = b.scene.triangles[0];
  check_vec(ta.p1, 1, 2, 3);
  check_vec(ta.p2, 1, 4, 3);   // (1,0,0)
  check_vec(ta.p3, -1, 2, 3);  // (0,1,0)
  check_vec(tb.p1, ta.p1.x, ta.p1.y, ta.p1.z);
  check_vec(tb.p2, ta.p2.x, ta.p2.y, ta.p2.z);
  check_vec(tb.p3, ta.p3.x, ta.p3.y, ta.p3.z);
}

TEST_CASE("transform elements compose in document order", "[collada]") {
  SECTION("translate then rotate: the rotation applies first") {
    const Loaded l = load(triangle_doc("<translate>1 0 0</translate><rotate>0 0 1 90</rotate>"));
    check_vec(l.scene.triangles.at(0).p1, 1, 0, 0);
    check_vec(l.scene.triangles.at(0).p2, 1, 1, 0);
  }
  SECTION("rotate then translate: the translation is rotated") {
    const Loaded l = load(triangle_doc("<rotate>0 0 1 90</rotate><translate>1 0 0</translate>"));
    check_vec(l.scene.triangles.at(0).p1, 0, 1, 0);
    check_vec(l.scene.triangles.at(0).p2, 0, 2, 0);
  }
  SECTION("two matrices multiply left to right") {
    const Loaded l = load(triangle_doc("<matrix>1 0 0 5 0 1 0 0 0 0 1 0 0 0 0 1</matrix>"
                                       "<matrix>3 0 0 0 0 3 0 0 0 0 3 0 0 0 0 1</matrix>"));
    check_vec(l.scene.triangles.at(0).p2, 8, 0, 0);
  }
  SECTION("the rotation axis need not be unit length and the angle is in degrees") {
    const Loaded l = load(triangle_doc("<rotate>0 0 5 180</rotate>"));
    check_vec(l.scene.triangles.at(0).p2, -1, 0, 0);
  }
  SECTION("non-uniform scale") {
    const Loaded l = load(triangle_doc("<scale>2 3 4</scale>"));
    check_vec(l.scene.triangles.at(0).p2, 2, 0, 0);
    check_vec(l.scene.triangles.at(0).p3, 0, 3, 0);
  }
}

TEST_CASE("lookat places the local frame at the eye looking at the interest point", "[collada]") {
  SECTION("looking down -Z is a pure translation") {
    const Loaded l = load(triangle_doc("<lookat>1 2 3  1 2 0  0 1 0</lookat>"));
    check_vec(l.scene.triangles.at(0).p1, 1, 2, 3);
    check_vec(l.scene.triangles.at(0).p2, 2, 2, 3);
  }
  SECTION("looking along +X: local -Z goes to +X, local +X to +Z, up stays +Y") {
    Doc d;
    d.geometries = mesh("g", {0, 0, -1, 1, 0, 0, 0, 1, 0}, polylist("g", "3", "0 1 2"));
    d.nodes = node("<lookat>0 0 0  4 0 0  0 1 0</lookat>", instance_geometry("g"));
    const Loaded l = load(d);
    check_vec(l.scene.triangles.at(0).p1, 1, 0, 0);
    check_vec(l.scene.triangles.at(0).p2, 0, 0, 1);
    check_vec(l.scene.triangles.at(0).p3, 0, 1, 0);
  }
}

TEST_CASE("malformed transforms are errors naming the element", "[collada][errors]") {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"<matrix>1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1 0</matrix>", "<matrix>"},
      {"<matrix>1 0 0 0 0 1 0 0 0 0 1 0 0 0 x</matrix>", "<matrix>"},  // short and not numeric
      {"<matrix>1 0 0 0 0 1 0 0 0 0 1 0 0 0 nan</matrix>", "<matrix>"},  // short and not finite
      {"<matrix>1 0 0 nan 0 1 0 0 0 0 1 0 0 0 0 1</matrix>", "<matrix>"},
      {"<matrix>1 0 0 inf 0 1 0 0 0 0 1 0 0 0 0 1</matrix>", "<matrix>"},
      {"<translate>1 2</translate>", "<translate>"},
      {"<rotate>0 0 1</rotate>", "<rotate>"},
      {"<rotate>0 0 0 45</rotate>", "<rotate>"},
      {"<scale>1 1 x</scale>", "<scale>"},
      {"<lookat>0 0 5 0 0 0 0 1</lookat>", "<lookat>"},
      {"<lookat>0 0 5 0 0 0 0 0 1</lookat>", "<lookat>"},  // up parallel to the view
  };
  for (const auto& c : cases) {
    SECTION(c.first) { CHECK_THAT(error_of(triangle_doc(c.first)), Contains(c.second)); }
  }
}

TEST_CASE("a <matrix> with fewer than 16 numbers reads the missing ones as 0, with a warning (course files)",
          "[collada]") {
  SECTION("the camera matrix of the course's CBgems.dae: 15 numbers, the camera still looks along -Z") {
    Doc d = triangle_doc();
    d.up_axis = "Z_UP";
    d.cameras = camera("cam", "<xfov>49.13434</xfov><aspect_ratio>1.777778</aspect_ratio>");
    d.nodes += node("<matrix sid=\"transform\">-1 0 0 0 0 0 1 3 0 0 0 0 0 0 1</matrix>",
                    "<instance_camera url=\"#cam\"/>", "Camera");
    const Loaded l = load(d);
    CHECK(has_warning(l, "<matrix>", "15 numbers"));
    CHECK(has_warning(l, "(line ", "read as 0"));
    // Zero fill gives rows (-1 0 0 0) (0 0 1 3) (0 0 0 0); the point ahead of
    // the camera, (0 0 -1), goes to (0, 2, 0) in the file, (0, 0, 2) in the
    // world: the camera looks along -Z from +Z, as in the course.
    check_vec(l.scene.camera.axis_z, 0, 0, 1);
    CHECK(l.scene.camera.position.z > 1);
  }
  SECTION("geometry under a short matrix uses the zero-filled rows and an affine bottom row") {
    const Loaded l = load(triangle_doc("<matrix>2 0 0 1  0 2 0 0  0 0 2</matrix>"));
    CHECK(has_warning(l, "<matrix>", "11 numbers"));
    REQUIRE(l.scene.triangles.size() == 1);
    check_vec(l.scene.triangles[0].p1, 1, 0, 0);
    check_vec(l.scene.triangles[0].p2, 3, 0, 0);
    check_vec(l.scene.triangles[0].p3, 1, 2, 0);
  }
  SECTION("one warning per element, however often its node is instanced") {
    Doc d = triangle_doc();
    d.library_nodes = node("<matrix>1 0 0 0 0 1 0 0 0 0 1 0 0 0 0</matrix>", instance_geometry("tri"), "lib");
    d.nodes = node("", "<instance_node url=\"#lib\"/><instance_node url=\"#lib\"/><instance_node url=\"#lib\"/>");
    const Loaded l = load(d);
    CHECK(l.scene.triangles.size() == 3);
    int n = 0;
    for (const std::string& w : l.warnings) n += w.find("<matrix>") != std::string::npos;
    CHECK(n == 1);
  }
}

// ---- Nodes -----------------------------------------------------------------------

TEST_CASE("nested nodes accumulate parent transforms", "[collada]") {
  Doc d = triangle_doc();
  d.nodes = node("<translate>1 0 0</translate>",
                 node("<scale>2 2 2</scale>", instance_geometry("tri") +
                                                  node("<rotate>0 0 1 90</rotate>", instance_geometry("tri"))));
  const Loaded l = load(d);
  REQUIRE(l.scene.triangles.size() == 2);
  check_vec(l.scene.triangles[0].p2, 3, 0, 0);  // T * S * (1,0,0)
  check_vec(l.scene.triangles[1].p2, 1, 2, 0);  // T * S * R * (1,0,0)
  check_vec(l.scene.triangles[1].p3, -1, 0, 0);
}

TEST_CASE("instance_node places library nodes under the instancing node", "[collada]") {
  Doc d = triangle_doc();
  d.library_nodes = node("<translate>0 5 0</translate>", instance_geometry("tri"), "lib");
  d.nodes = node("<translate>1 0 0</translate>", "<instance_node url=\"#lib\"/>") +
            node("<translate>0 0 7</translate>", "<instance_node url=\"#lib\"/>");
  const Loaded l = load(d);
  REQUIRE(l.scene.triangles.size() == 2);
  check_vec(l.scene.triangles[0].p1, 1, 5, 0);
  check_vec(l.scene.triangles[1].p1, 0, 5, 7);
}

TEST_CASE("a node that instances itself is an error, not a crash", "[collada][errors]") {
  Doc d = triangle_doc();
  d.library_nodes = node("", instance_geometry("tri") + "<instance_node url=\"#loop\"/>", "loop");
  d.nodes = node("", "<instance_node url=\"#loop\"/>");
  CHECK_THAT(error_of(d), Contains("<instance_node>") && Contains("cycle"));
}

TEST_CASE("a misspelt element inside a node is reported with a warning naming it and its line", "[collada]") {
  Doc d = triangle_doc();
  d.nodes = node("", instance_geometry("tri")) +
            "\n<node id=\"lost\">\n<instance_geometery url=\"#tri\"/>\n</node>\n";
  const Loaded l = load(d);
  CHECK(l.scene.triangles.size() == 1);
  CHECK(has_warning(l, "<instance_geometery> (line ", "<node id=\"lost\">"));
  CHECK(has_warning(l, "<instance_geometery>", "ignored"));
}

TEST_CASE("exponential instancing stops at the primitive limit before the memory is taken", "[collada][errors]") {
  // A 256-triangle mesh placed by four levels of 16 instance_nodes each:
  // 65536 instances, 16.8 million triangles (1.3 GB) from a few kilobytes.
  std::vector<double> xyz;
  std::string vcount, p;
  for (int i = 0; i < 256; ++i) {
    const double x = i;
    for (double v : {x, 0.0, 0.0, x + 1, 0.0, 0.0, x, 1.0, 0.0}) xyz.push_back(v);
    vcount += "3 ";
    p += std::to_string(3 * i) + " " + std::to_string(3 * i + 1) + " " + std::to_string(3 * i + 2) + " ";
  }
  Doc d;
  d.geometries = mesh("g", xyz, polylist("g", vcount, p));
  d.library_nodes = node("", instance_geometry("g"), "n0");
  for (int level = 1; level <= 4; ++level) {
    std::string inner;
    for (int k = 0; k < 16; ++k)
      inner += "<instance_node url=\"#n" + std::to_string(level - 1) + "\"/>";
    d.library_nodes += node("", inner, "n" + std::to_string(level));
  }
  d.nodes = node("", "<instance_node url=\"#n4\"/>");
  const std::string text = d.str();
  CHECK(text.size() < 20000);
  // With the address space limited to 1.5 GB the whole scene cannot be
  // allocated: the loader must stop at its limit first.
  rlimit old{};
  REQUIRE(getrlimit(RLIMIT_AS, &old) == 0);
  const rlimit lim{rlim_t(1536) << 20, old.rlim_max};
  REQUIRE(setrlimit(RLIMIT_AS, &lim) == 0);
  const std::string m = error_of(text);
  setrlimit(RLIMIT_AS, &old);
  CHECK_THAT(m, Contains("4000000") && Contains("limit"));
  CHECK_THAT(m, !Contains("memory"));
}
