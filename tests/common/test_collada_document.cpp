// Tests of the COLLADA document as a whole: reading the file, the up axis,
// the visual scene, references between elements, and elements the loader
// does not know.
#include <catch2/catch.hpp>

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "tests/common/collada_documents.h"
#include "tests/support.h"

using Catch::Matchers::Contains;
using namespace pt::test::dae;

// ---- Reading the file ------------------------------------------------------------

TEST_CASE("unreadable files and non-COLLADA content are errors", "[collada][errors]") {
  SECTION("missing file") {
    pt::test::TempDir dir;
    const std::string path = dir.file("nope.dae");
    REQUIRE_THROWS_WITH(pt::load_collada(path), Contains(path) && Contains("cannot open"));
  }
  SECTION("a folder") {
    pt::test::TempDir dir;
    REQUIRE_THROWS_AS(pt::load_collada(dir.path()), pt::SceneError);
  }
  SECTION("not XML: the parser's line number is reported") {
    CHECK_THAT(error_of("<?xml version=\"1.0\"?>\n<COLLADA>\n<asset>\n</COLLADA>\n"),
               Contains("line 3") && Contains("not valid XML"));
  }
  SECTION("empty file") { CHECK_THAT(error_of(""), Contains("empty")); }
  SECTION("XML that is not COLLADA") {
    CHECK_THAT(error_of("<html><body/></html>"), Contains("<html>") && Contains("<COLLADA>"));
  }
}

TEST_CASE("a scene without triangles or spheres is an error", "[collada][errors]") {
  Doc d;
  d.cameras = camera("cam", "<xfov>40</xfov>");
  d.nodes = node("<translate>0 0 5</translate>", "<instance_camera url=\"#cam\"/>");
  CHECK_THAT(error_of(d), Contains("<visual_scene id=\"Scene\">") && Contains("no triangles or spheres"));
}

// ---- Up axis and visual scene ----------------------------------------------------

TEST_CASE("up axis maps file coordinates to world Y-up", "[collada]") {
  const std::vector<std::pair<std::string, pt::Vec3>> cases = {
      {"Y_UP", {1, 2, 3}}, {"Z_UP", {-1, 3, 2}}, {"X_UP", {2, 1, -3}}};
  for (const auto& c : cases) {
    SECTION(c.first) {
      Doc d;
      d.up_axis = c.first;
      d.geometries = mesh("g", {1, 2, 3, 2, 2, 3, 1, 3, 3}, polylist("g", "3", "0 1 2"));
      d.nodes = node("", instance_geometry("g"));
      const Loaded l = load(d);
      REQUIRE(l.scene.triangles.size() == 1);
      check_vec(l.scene.triangles[0].p1, c.second.x, c.second.y, c.second.z);
    }
  }
  SECTION("whitespace around the value is accepted") {
    Doc d = triangle_doc();
    d.up_axis = "\n  Z_UP  ";
    CHECK(load(d).scene.triangles.size() == 1);
  }
}

TEST_CASE("the up axis is required and must be known", "[collada][errors]") {
  Doc d = triangle_doc();
  SECTION("missing") {
    d.up_axis = "";
    CHECK_THAT(error_of(d), Contains("<asset>") && Contains("up_axis"));
  }
  SECTION("unknown") {
    d.up_axis = "W_UP";
    CHECK_THAT(error_of(d), Contains("<up_axis>") && Contains("'W_UP'"));
  }
}

TEST_CASE("the visual scene is the one <scene> names, else the first", "[collada]") {
  Doc d;
  d.geometries = mesh("tri", {0, 0, 0, 1, 0, 0, 0, 1, 0}, polylist("tri", "3", "0 1 2"));
  d.nodes = node("", instance_geometry("tri"));
  d.more_scenes = "<visual_scene id=\"Other\">" + node("<translate>0 0 5</translate>", instance_geometry("tri")) +
                  "</visual_scene>";
  SECTION("named") {
    d.scene = "<scene><instance_visual_scene url=\"#Other\"/></scene>";
    CHECK(load(d).scene.triangles.at(0).p1.z == Approx(5));
  }
  SECTION("first") {
    d.scene = "";
    CHECK(load(d).scene.triangles.at(0).p1.z == Approx(0));
  }
}

// ---- References ------------------------------------------------------------------

TEST_CASE("dangling references name the referring element", "[collada][errors]") {
  Doc d = triangle_doc();
  d.effects = effect_common("fx", "phong", "1 1 1 1");
  d.materials = material("mat", "fx");
  d.cameras = camera("cam", "<xfov>40</xfov>");
  d.lights = light("L", "<point><color>1 1 1</color></point>");
  std::string element;
  SECTION("instance_geometry") {
    d.nodes = node("", instance_geometry("nothing"));
    element = "<instance_geometry>";
  }
  SECTION("instance_light") {
    d.nodes += node("", instance_light("nothing"));
    element = "<instance_light>";
  }
  SECTION("instance_camera") {
    d.nodes += node("", "<instance_camera url=\"#nothing\"/>");
    element = "<instance_camera>";
  }
  SECTION("instance_material") {
    d.nodes = node("", instance_geometry("tri", {{"s", "nothing"}}));
    element = "<instance_material>";
  }
  SECTION("instance_effect") {
    d.materials = material("mat", "nothing");
    d.nodes = node("", instance_geometry("tri", {{"s", "mat"}}));
    element = "<instance_effect>";
  }
  SECTION("input source") {
    d.geometries = mesh("tri", {0, 0, 0, 1, 0, 0, 0, 1, 0},
                        "<polylist count=\"1\">" + vertex_input("tri") +
                            "<input semantic=\"NORMAL\" source=\"#nothing\" offset=\"1\"/>"
                            "<vcount>3</vcount><p>0 0 1 0 2 0</p></polylist>");
    element = "<input>";
  }
  SECTION("instance_node") {
    d.nodes += node("", "<instance_node url=\"#nothing\"/>");
    element = "<instance_node>";
  }
  SECTION("instance_visual_scene") {
    d.scene = "<scene><instance_visual_scene url=\"#nothing\"/></scene>";
    element = "<instance_visual_scene>";
  }
  const std::string m = error_of(d);
  CHECK_THAT(m, Contains(element) && Contains("'#nothing'") && Contains("refers to no element"));
}

TEST_CASE("a reference to an element of the wrong kind is an error", "[collada][errors]") {
  Doc d = triangle_doc();
  d.lights = light("L", "<point><color>1 1 1</color></point>");
  d.nodes = node("", "<instance_geometry url=\"#L\"/>");
  CHECK_THAT(error_of(d), Contains("<instance_geometry>") && Contains("<light>"));
}

// ---- Unknown elements ------------------------------------------------------------

TEST_CASE("unknown elements that would silently lose content are warned about everywhere the loader reads",
          "[collada]") {
  struct Case {
    const char* name;
    std::function<void(Doc&)> edit;
    const char* element;
  };
  const std::vector<Case> cases = {
      {"in the visual scene", [](Doc& d) { d.nodes += "<nod id=\"n\">" + instance_geometry("tri") + "</nod>"; },
       "<nod id=\"n\">"},
      {"in a mesh",
       [](Doc& d) {
         d.geometries = mesh("tri", {0, 0, 0, 1, 0, 0, 0, 1, 0},
                             polylist("tri", "3", "0 1 2") + "<triangels count=\"1\"><p>0 1 2</p></triangels>");
       },
       "<triangels>"},
      {"in a primitive list",
       [](Doc& d) {
         d.geometries = mesh("tri", {0, 0, 0, 1, 0, 0, 0, 1, 0},
                             "<polygons count=\"1\">" + vertex_input("tri") + "<p>0 1 2</p><P>0 2 1</P></polygons>");
       },
       "<P>"},
      {"in an instance_geometry",
       [](Doc& d) {
         d.materials = material("m", "fx");
         d.effects = effect_common("fx", "lambert", "1 0 0");
         d.nodes = node("", "<instance_geometry url=\"#tri\"><bind_materal><technique_common>"
                            "<instance_material symbol=\"s\" target=\"#m\"/></technique_common></bind_materal>"
                            "</instance_geometry>");
       },
       "<bind_materal>"},
      {"in a bind_material",
       [](Doc& d) {
         d.materials = material("m", "fx");
         d.effects = effect_common("fx", "lambert", "1 0 0");
         d.nodes = node("", "<instance_geometry url=\"#tri\"><bind_material><technique_common>"
                            "<instance_materiel symbol=\"s\" target=\"#m\"/></technique_common></bind_material>"
                            "</instance_geometry>");
       },
       "<instance_materiel>"},
      {"in a perspective",
       [](Doc& d) {
         d.cameras = camera("cam", "<xfov>40</xfov><yfovv>10</yfovv>");
         d.nodes += node("<translate>0 0 5</translate>", "<instance_camera url=\"#cam\"/>");
       },
       "<yfovv>"},
      {"in a point light",
       [](Doc& d) {
         d.lights = "<light id=\"L\"><technique_common><point><color>1 1 1</color>"
                    "<linear_atenuation>1</linear_atenuation></point></technique_common></light>";
         d.nodes += node("", "<instance_light url=\"#L\"/>");
       },
       "<linear_atenuation>"},
      {"in a CGL material",
       [](Doc& d) {
         d.materials = material("m", "fx");
         d.effects = effect_cgl("fx", "<glass><iorr>2</iorr></glass>");
         d.nodes = node("", instance_geometry("tri", {{"s", "m"}}));
       },
       "<iorr>"},
      {"in a profile_COMMON shading model",
       [](Doc& d) {
         d.materials = material("m", "fx");
         d.effects = "<effect id=\"fx\"><profile_COMMON><technique sid=\"common\"><phong><difuse><color>1 0 0 1"
                     "</color></difuse></phong></technique></profile_COMMON></effect>";
         d.nodes = node("", instance_geometry("tri", {{"s", "m"}}));
       },
       "<difuse>"},
      {"in <scene>",
       [](Doc& d) { d.scene = "<scene><instance_visual_scen url=\"#Scene\"/></scene>"; },
       "<instance_visual_scen>"},
  };
  for (const Case& c : cases) {
    SECTION(c.name) {
      Doc d = triangle_doc();
      c.edit(d);
      const Loaded l = load(d);
      INFO("warnings:");
      for (const std::string& w : l.warnings) INFO(w);
      CHECK(has_warning(l, std::string(c.element) + " (line ", "ignored"));
    }
  }
}

TEST_CASE("elements COLLADA allows but the loader does not need stay quiet", "[collada]") {
  Doc d = triangle_doc();
  d.cameras = camera("cam", "<xfov sid=\"xfov\">40</xfov><znear>0.1</znear><zfar>100</zfar>");
  d.materials = material("m", "fx");
  d.effects = "<effect id=\"fx\"><profile_COMMON><technique sid=\"common\"><phong><emission><color>0 0 0 1</color>"
              "</emission><ambient><color>0 0 0 1</color></ambient><diffuse><color>1 0 0 1</color></diffuse>"
              "<specular><color>0 0 0 1</color></specular><shininess><float>1</float></shininess>"
              "<index_of_refraction><float>1</float></index_of_refraction></phong></technique>"
              "<extra/></profile_COMMON></effect>";
  d.lights = "<light id=\"L\"><technique_common><point><color>1 1 1</color><constant_attenuation>1"
             "</constant_attenuation><linear_attenuation>0</linear_attenuation><quadratic_attenuation>0"
             "</quadratic_attenuation></point></technique_common></light>";
  d.nodes = "<node id=\"a\"><asset/><translate>0 0 0</translate><instance_geometry url=\"#tri\"><bind_material>"
            "<technique_common><instance_material symbol=\"s\" target=\"#m\"/></technique_common>"
            "<extra/></bind_material><extra/></instance_geometry><extra><technique profile=\"blender\">"
            "<layer>L1</layer></technique></extra></node>" +
            node("<translate>0 0 5</translate>", "<instance_camera url=\"#cam\"/><instance_light url=\"#L\"/>") +
            "<extra/>";
  const Loaded l = load(d);
  for (const std::string& w : l.warnings) FAIL_CHECK("unexpected warning: " << w);
  CHECK(l.scene.triangles.size() == 1);
}
