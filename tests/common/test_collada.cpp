// Unit tests of the COLLADA loader on small hand-written documents.
#include <sys/resource.h>

#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <initializer_list>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "collada.h"
#include "support.h"

namespace {

using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;

constexpr double kPi = 3.14159265358979323846;
double deg(double r) { return r * 180.0 / kPi; }
double rad(double d) { return d * kPi / 180.0; }

// ---- Building documents ---------------------------------------------------

std::string list(const std::vector<double>& v) {
  std::ostringstream s;
  s.precision(17);
  for (size_t i = 0; i < v.size(); ++i) s << (i ? " " : "") << v[i];
  return s.str();
}

// A <geometry> holding a mesh with positions `xyz` and primitive lists
// `prims` (whose VERTEX input is "#ID-vertices").
std::string mesh(const std::string& id, const std::string& xyz, size_t count, const std::string& prims,
                 const std::string& extra_sources = "") {
  return "<geometry id=\"" + id + "\"><mesh><source id=\"" + id + "-positions\"><float_array id=\"" + id +
         "-positions-array\" count=\"" + std::to_string(3 * count) + "\">" + xyz +
         "</float_array><technique_common><accessor source=\"#" + id + "-positions-array\" count=\"" +
         std::to_string(count) +
         "\" stride=\"3\"><param name=\"X\" type=\"float\"/><param name=\"Y\" type=\"float\"/>"
         "<param name=\"Z\" type=\"float\"/></accessor></technique_common></source>" +
         extra_sources + "<vertices id=\"" + id + "-vertices\"><input semantic=\"POSITION\" source=\"#" + id +
         "-positions\"/></vertices>" + prims + "</mesh></geometry>";
}

std::string mesh(const std::string& id, const std::vector<double>& xyz, const std::string& prims) {
  return mesh(id, list(xyz), xyz.size() / 3, prims);
}

std::string vertex_input(const std::string& id) {
  return "<input semantic=\"VERTEX\" source=\"#" + id + "-vertices\" offset=\"0\"/>";
}

std::string polylist(const std::string& id, const std::string& vcount, const std::string& p,
                     const std::string& material = "") {
  std::istringstream vs(vcount);
  int n = 0, c = 0;
  while (vs >> c) ++n;
  return "<polylist" + (material.empty() ? "" : " material=\"" + material + "\"") + " count=\"" +
         std::to_string(n) + "\">" + vertex_input(id) + "<vcount>" + vcount + "</vcount><p>" + p +
         "</p></polylist>";
}

std::string triangles(const std::string& id, int count, const std::string& p, const std::string& material = "") {
  return "<triangles" + (material.empty() ? "" : " material=\"" + material + "\"") + " count=\"" +
         std::to_string(count) + "\">" + vertex_input(id) + "<p>" + p + "</p></triangles>";
}

std::string bind(const std::vector<std::pair<std::string, std::string>>& symbol_target) {
  if (symbol_target.empty()) return "";
  std::string s = "<bind_material><technique_common>";
  for (const auto& st : symbol_target)
    s += "<instance_material symbol=\"" + st.first + "\" target=\"#" + st.second + "\"/>";
  return s + "</technique_common></bind_material>";
}

std::string instance_geometry(const std::string& id,
                              const std::vector<std::pair<std::string, std::string>>& symbol_target = {}) {
  return "<instance_geometry url=\"#" + id + "\">" + bind(symbol_target) + "</instance_geometry>";
}

std::string node(const std::string& transforms, const std::string& content, const std::string& id = "") {
  return "<node" + (id.empty() ? "" : " id=\"" + id + "\"") + ">" + transforms + content + "</node>";
}

std::string camera(const std::string& id, const std::string& perspective) {
  return "<camera id=\"" + id + "\"><optics><technique_common><perspective>" + perspective +
         "</perspective></technique_common></optics></camera>";
}

std::string effect_common(const std::string& id, const std::string& model, const std::string& color) {
  return "<effect id=\"" + id + "\"><profile_COMMON><technique sid=\"common\"><" + model + "><diffuse><color>" +
         color + "</color></diffuse></" + model + "></technique></profile_COMMON></effect>";
}

std::string effect_cgl(const std::string& id, const std::string& cgl) {
  return "<effect id=\"" + id + "\">" + "<profile_COMMON><technique sid=\"common\"><phong><diffuse><color>" +
         "0.9 0.9 0.9 1</color></diffuse></phong></technique></profile_COMMON>" +
         "<extra><technique profile=\"CGL\">" + cgl + "</technique></extra></effect>";
}

std::string material(const std::string& id, const std::string& effect) {
  return "<material id=\"" + id + "\"><instance_effect url=\"#" + effect + "\"/></material>";
}

struct Doc {
  std::string up_axis = "Y_UP";  // empty: no <up_axis>
  std::string cameras, lights, effects, materials, geometries, library_nodes;
  std::string nodes;         // contents of <visual_scene id="Scene">
  std::string more_scenes;   // further <visual_scene> elements
  std::string scene = "<scene><instance_visual_scene url=\"#Scene\"/></scene>";

  std::string str() const {
    std::string s = "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n"
                    "<COLLADA xmlns=\"http://www.collada.org/2005/11/COLLADASchema\" version=\"1.4.1\">\n";
    s += "<asset>" + (up_axis.empty() ? std::string() : "<up_axis>" + up_axis + "</up_axis>") + "</asset>\n";
    s += "<library_cameras>" + cameras + "</library_cameras>\n";
    s += "<library_lights>" + lights + "</library_lights>\n";
    s += "<library_effects>" + effects + "</library_effects>\n";
    s += "<library_materials>" + materials + "</library_materials>\n";
    s += "<library_geometries>" + geometries + "</library_geometries>\n";
    s += "<library_nodes>" + library_nodes + "</library_nodes>\n";
    s += "<library_visual_scenes><visual_scene id=\"Scene\">" + nodes + "</visual_scene>" + more_scenes +
         "</library_visual_scenes>\n";
    s += scene + "\n</COLLADA>\n";
    return s;
  }
};

// A document with one triangle (0,0,0) (1,0,0) (0,1,0) in geometry "tri"
// under a node with `transforms`.
Doc triangle_doc(const std::string& transforms = "") {
  Doc d;
  d.geometries = mesh("tri", {0, 0, 0, 1, 0, 0, 0, 1, 0}, polylist("tri", "3", "0 1 2"));
  d.nodes = node(transforms, instance_geometry("tri"));
  return d;
}

// ---- Loading ---------------------------------------------------------------------

struct Loaded {
  pt::Scene scene;
  std::vector<std::string> warnings;
  std::string path;
};

Loaded load(const std::string& text) {
  pt::test::TempDir dir;
  Loaded r;
  r.path = dir.file("scene.dae");
  pt::test::write_text(r.path, text);
  r.scene = pt::load_collada(r.path, &r.warnings);
  return r;
}

Loaded load(const Doc& d) { return load(d.str()); }

// The message of the SceneError that loading `text` throws. Checks the
// message is one line starting with the file's path.
std::string error_of(const std::string& text) {
  pt::test::TempDir dir;
  const std::string path = dir.file("bad-scene.dae");
  pt::test::write_text(path, text);
  try {
    pt::load_collada(path);
  } catch (const pt::SceneError& e) {
    const std::string m = e.what();
    CHECK_THAT(m, StartsWith(path + ": "));
    CHECK(m.find('\n') == std::string::npos);
    return m;
  }
  FAIL("loading did not throw a SceneError");
  return "";
}

std::string error_of(const Doc& d) { return error_of(d.str()); }

bool has_warning(const Loaded& l, const std::string& a, const std::string& b = "") {
  for (const std::string& w : l.warnings) {
    if (w.rfind(l.path + ": ", 0) != 0 || w.find('\n') != std::string::npos) continue;
    if (w.find(a) != std::string::npos && (b.empty() || w.find(b) != std::string::npos)) return true;
  }
  return false;
}

void check_vec(const pt::Vec3& v, double x, double y, double z, double eps = 1e-5) {
  INFO("got (" << v.x << ", " << v.y << ", " << v.z << "), want (" << x << ", " << y << ", " << z << ")");
  CHECK(v.x == Approx(x).margin(eps));
  CHECK(v.y == Approx(y).margin(eps));
  CHECK(v.z == Approx(z).margin(eps));
}

void check_vec(const pt::Vec3d& v, double x, double y, double z, double eps = 1e-9) {
  check_vec(pt::Vec3(v), x, y, z, std::max(eps, 1e-6));
}

}  // namespace

// ---- Up axis and transforms ---------------------------------------------------------------

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

TEST_CASE("number syntax: signs, bare decimal points, exponents, extreme values", "[collada]") {
  Doc d;
  d.geometries = mesh("g", "+1 .5 -2e0   1E1 5. 1e-400   \n\t0 -.25 +3", 3, polylist("g", "3", "0 1 2"));
  d.nodes = node("", instance_geometry("g"));
  const Loaded l = load(d);
  REQUIRE(l.scene.triangles.size() == 1);
  check_vec(l.scene.triangles[0].p1, 1, 0.5, -2);
  check_vec(l.scene.triangles[0].p2, 10, 5, 0);  // 1e-400 underflows to 0
  check_vec(l.scene.triangles[0].p3, 0, -0.25, 3);
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

// ---- Primitive lists ---------------------------------------------------------------

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

// ---- Normals ----------------------------------------------------------------------------

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

// ---- Lights ----------------------------------------------------------------------

namespace {
std::string light(const std::string& id, const std::string& common, const std::string& cgl = "") {
  std::string s = "<light id=\"" + id + "\">";
  if (!common.empty()) s += "<technique_common>" + common + "</technique_common>";
  if (!cgl.empty()) s += "<extra><technique profile=\"CGL\">" + cgl + "</technique></extra>";
  return s + "</light>";
}
std::string instance_light(const std::string& id) { return "<instance_light url=\"#" + id + "\"/>"; }
}  // namespace

TEST_CASE("area light: centre, edge vectors and direction from the node transform", "[collada][lights]") {
  Doc d = triangle_doc();
  d.lights = light("L", "<point><color>1 1 1</color></point>", "<area><color>3 4 5</color></area>");
  d.nodes += node("<translate>0 2 0</translate><rotate>1 0 0 -90</rotate><scale>0.5 0.25 1</scale>",
                  instance_light("L"));
  const Loaded l = load(d);
  REQUIRE(l.scene.lights.size() == 1);
  const pt::Light& a = l.scene.lights[0];
  CHECK(a.type == pt::LightType::Area);  // the CGL profile wins over technique_common
  check_vec(a.radiance, 3, 4, 5);
  check_vec(a.position, 0, 2, 0);
  check_vec(a.dim_x, -0.5, 0, 0);
  check_vec(a.dim_y, 0, 0, -0.25);
  check_vec(a.direction, 0, -1, 0);
}

TEST_CASE("point light: position, intensity and attenuation", "[collada][lights]") {
  Doc d = triangle_doc();
  d.lights = light("P",
                   "<point><color>1 2 3</color><constant_attenuation>0.5</constant_attenuation>"
                   "<linear_attenuation>0.25</linear_attenuation>"
                   "<quadratic_attenuation>0.125</quadratic_attenuation></point>") +
             light("Q", "<point><color>1 1 1</color></point>");
  d.nodes += node("<translate>1 2 3</translate>", instance_light("P") + instance_light("Q"));
  const Loaded l = load(d);
  REQUIRE(l.scene.lights.size() == 2);
  const pt::Light& p = l.scene.lights[0];
  CHECK(p.type == pt::LightType::Point);
  check_vec(p.position, 1, 2, 3);
  check_vec(p.radiance, 1, 2, 3);
  CHECK(p.constant_attenuation == Approx(0.5));
  CHECK(p.linear_attenuation == Approx(0.25));
  CHECK(p.quadratic_attenuation == Approx(0.125));
  // Defaults: no fall-off.
  const pt::Light& q = l.scene.lights[1];
  CHECK(q.constant_attenuation == 1);
  CHECK(q.linear_attenuation == 0);
  CHECK(q.quadratic_attenuation == 0);
}

TEST_CASE("directional light uses the node's rotation only", "[collada][lights]") {
  Doc d = triangle_doc();
  d.lights = light("D", "<directional><color>0.5 0.5 0.5</color></directional>");
  SECTION("with translation and scale in the transform") {
    d.nodes += node("<translate>10 20 30</translate><rotate>1 0 0 -90</rotate><scale>2 2 2</scale>",
                    instance_light("D"));
    const Loaded l = load(d);
    REQUIRE(l.scene.lights.size() == 1);
    CHECK(l.scene.lights[0].type == pt::LightType::Directional);
    check_vec(l.scene.lights[0].direction, 0, -1, 0);
    check_vec(l.scene.lights[0].radiance, 0.5, 0.5, 0.5);
  }
  SECTION("in a <matrix> with a Z_UP file") {
    d.up_axis = "Z_UP";
    // Local -Z is (0.6, 0, -0.8) in file space: world (-0.6, -0.8, 0).
    d.nodes += node("<matrix>0.8 0 -0.6 7  0 1 0 8  0.6 0 0.8 9  0 0 0 1</matrix>", instance_light("D"));
    const Loaded l = load(d);
    check_vec(l.scene.lights.at(0).direction, -0.6, -0.8, 0);
  }
}

TEST_CASE("ambient light keeps its colour, spot and unknown lights are skipped with a warning",
          "[collada][lights]") {
  Doc d = triangle_doc();
  d.lights = light("A", "<ambient><color>0.1 0.2 0.3</color></ambient>") +
             light("S", "<spot><color>1 1 1</color></spot>") + light("U", "<laser><color>1 1 1</color></laser>");
  d.nodes += node("", instance_light("A") + instance_light("S") + instance_light("U"));
  const Loaded l = load(d);
  REQUIRE(l.scene.lights.size() == 1);
  CHECK(l.scene.lights[0].type == pt::LightType::Ambient);
  check_vec(l.scene.lights[0].radiance, 0.1, 0.2, 0.3);
  CHECK(has_warning(l, "<light id=\"S\">", "spot"));
  CHECK(has_warning(l, "<light id=\"U\">", "unknown light type <laser>"));
}

// ---- Materials ------------------------------------------------------------------------

TEST_CASE("CGL materials of every type and profile_COMMON diffuse", "[collada][materials]") {
  Doc d;
  d.effects = effect_cgl("e-emit", "<emission><radiance>10 20 30</radiance></emission>") +
              effect_cgl("e-mirror", "<mirror><reflectance>0.9 0.8 0.7</reflectance></mirror>") +
              effect_cgl("e-glass",
                         "<glass><reflectance>0.1 0.2 0.3</reflectance><transmittance>0.4 0.5 0.6"
                         "</transmittance><roughness>0.05</roughness><ior>1.45</ior></glass>") +
              effect_cgl("e-refr",
                         "<refraction><transmittance>0.7 0.8 0.9</transmittance><roughness>0.2</roughness>"
                         "<ior>1.33</ior></refraction>") +
              effect_cgl("e-micro", "<microfacet><alpha>0.3</alpha><eta>0.2 0.9 1.1</eta><k>3.9 2.4 2.2</k>"
                                    "</microfacet>") +
              effect_common("e-lambert", "lambert", "0.25 0.5 0.75 1") +
              effect_common("e-blinn", "blinn", "0.1 0.2 0.3");
  const std::vector<std::string> names = {"emit", "mirror", "glass", "refr", "micro", "lambert", "blinn"};
  std::string prims;
  std::vector<std::pair<std::string, std::string>> binding;
  for (const std::string& n : names) {
    d.materials += material(n, "e-" + n);
    prims += polylist("g", "3", "0 1 2", "s-" + n);
    binding.push_back({"s-" + n, n});
  }
  d.geometries = mesh("g", {0, 0, 0, 1, 0, 0, 0, 1, 0}, prims);
  d.nodes = node("", instance_geometry("g", binding));
  const Loaded l = load(d);
  REQUIRE(l.scene.triangles.size() == names.size());
  REQUIRE(l.scene.materials.size() == names.size());
  auto mat = [&](size_t i) -> const pt::Material& {
    const pt::Material& m = l.scene.materials.at(size_t(l.scene.triangles.at(i).material));
    CHECK(m.name == names[i]);
    return m;
  };
  const pt::Material& emit = mat(0);
  CHECK(emit.type == pt::MaterialType::Emission);
  check_vec(emit.emission, 10, 20, 30);
  check_vec(emit.albedo, 0, 0, 0);
  const pt::Material& mirror = mat(1);
  CHECK(mirror.type == pt::MaterialType::Mirror);
  check_vec(mirror.reflectance, 0.9, 0.8, 0.7);
  const pt::Material& glass = mat(2);
  CHECK(glass.type == pt::MaterialType::Glass);
  check_vec(glass.reflectance, 0.1, 0.2, 0.3);
  check_vec(glass.transmittance, 0.4, 0.5, 0.6);
  CHECK(glass.roughness == Approx(0.05));
  CHECK(glass.ior == Approx(1.45));
  const pt::Material& refr = mat(3);
  CHECK(refr.type == pt::MaterialType::Refraction);
  check_vec(refr.transmittance, 0.7, 0.8, 0.9);
  CHECK(refr.roughness == Approx(0.2));
  CHECK(refr.ior == Approx(1.33));
  const pt::Material& micro = mat(4);
  CHECK(micro.type == pt::MaterialType::Microfacet);
  CHECK(micro.alpha == Approx(0.3));
  check_vec(micro.eta, 0.2, 0.9, 1.1);
  check_vec(micro.k, 3.9, 2.4, 2.2);
  const pt::Material& lambert = mat(5);
  CHECK(lambert.type == pt::MaterialType::Diffuse);
  check_vec(lambert.albedo, 0.25, 0.5, 0.75);  // alpha ignored
  CHECK_FALSE(lambert.is_emissive());
  const pt::Material& blinn = mat(6);
  CHECK(blinn.type == pt::MaterialType::Diffuse);
  check_vec(blinn.albedo, 0.1, 0.2, 0.3);
}

TEST_CASE("material binding: fallbacks and de-duplication", "[collada][materials]") {
  Doc d = triangle_doc();
  d.effects = effect_common("fx-a", "phong", "0.1 0.1 0.1 1") + effect_common("fx-b", "phong", "0.2 0.2 0.2 1");
  d.materials = material("A", "fx-a") + material("B", "fx-b");
  d.geometries = mesh("tri", {0, 0, 0, 1, 0, 0, 0, 1, 0}, polylist("tri", "3", "0 1 2", "wanted"));
  SECTION("no bound material: the default diffuse 0.5") {
    d.nodes = node("", instance_geometry("tri"));
    const Loaded l = load(d);
    REQUIRE(l.scene.materials.size() == 1);
    const pt::Material& m = l.scene.materials[0];
    CHECK(m.name == "default");
    CHECK(m.type == pt::MaterialType::Diffuse);
    check_vec(m.albedo, 0.5, 0.5, 0.5);
    CHECK(l.scene.triangles.at(0).material == 0);
  }
  SECTION("an unmatched symbol takes the first instance_material") {
    d.nodes = node("", instance_geometry("tri", {{"other", "B"}, {"more", "A"}}));
    const Loaded l = load(d);
    CHECK(l.scene.materials.at(size_t(l.scene.triangles.at(0).material)).name == "B");
  }
  SECTION("one material per <material> used, shared between instances") {
    d.nodes = node("", instance_geometry("tri", {{"wanted", "A"}})) +
              node("<translate>0 0 1</translate>", instance_geometry("tri", {{"wanted", "A"}}));
    const Loaded l = load(d);
    REQUIRE(l.scene.triangles.size() == 2);
    CHECK(l.scene.materials.size() == 1);
    CHECK(l.scene.triangles[0].material == l.scene.triangles[1].material);
    CHECK(l.scene.materials[0].name == "A");
  }
}

// ---- Spheres ---------------------------------------------------------------------------

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

// ---- Camera ------------------------------------------------------------------------------

TEST_CASE("camera field of view from xfov, yfov and aspect_ratio", "[collada][camera]") {
  struct Case {
    const char* name;
    std::string perspective;
    double hfov, vfov;  // after the 4:3 fit
  };
  const double t30 = std::tan(rad(30));
  const std::vector<Case> cases = {
      // xfov 60 with aspect 2: yfov is narrower than 4:3 allows, so it widens.
      {"xfov + aspect", "<xfov>60</xfov><aspect_ratio>2</aspect_ratio>", 60, deg(2 * std::atan(t30 * 0.75))},
      // yfov 60 with aspect 1: xfov too narrow for 4:3, widened.
      {"yfov + aspect", "<yfov>60</yfov><aspect_ratio>1</aspect_ratio>", deg(2 * std::atan(t30 * 4 / 3)), 60},
      // Both given: both used (here already 4:3 exactly).
      {"xfov + yfov", "<xfov>60</xfov><yfov>" + std::to_string(deg(2 * std::atan(t30 * 0.75))) + "</yfov>", 60,
       deg(2 * std::atan(t30 * 0.75))},
      // Only xfov: aspect 4:3 assumed.
      {"xfov alone", "<xfov>60</xfov>", 60, deg(2 * std::atan(t30 * 0.75))},
      {"yfov alone", "<yfov>60</yfov>", deg(2 * std::atan(t30 * 4 / 3)), 60},
  };
  for (const Case& c : cases) {
    SECTION(c.name) {
      Doc d = triangle_doc();
      d.cameras = camera("cam", c.perspective);
      d.nodes += node("<translate>0 0 5</translate>", "<instance_camera url=\"#cam\"/>");
      const Loaded l = load(d);
      CHECK(l.warnings.empty());
      CHECK(l.scene.camera.hfov_deg == Approx(c.hfov).epsilon(1e-6));
      CHECK(l.scene.camera.vfov_deg == Approx(c.vfov).epsilon(1e-6));
      CHECK(l.scene.camera.near_clip == 0.001);
      CHECK(l.scene.camera.far_clip == 1000.0);
    }
  }
}

TEST_CASE("camera placement follows the course's rule", "[collada][camera]") {
  // Bounds of the triangle: centre (0.5, 0.5, 0), extent length sqrt(2).
  Doc d = triangle_doc();
  d.cameras = camera("cam", "<xfov>45</xfov><aspect_ratio>1.5</aspect_ratio><znear>0.25</znear><zfar>50</zfar>");
  const double dist = 1.5 * std::sqrt(2.0);
  SECTION("the node's translation sets the direction, not the position") {
    d.nodes += node("<translate>0 0 5</translate>", "<instance_camera url=\"#cam\"/>");
    const Loaded l = load(d);
    check_vec(l.scene.camera.position, 0.5, 0.5, dist);
    check_vec(l.scene.camera.target, 0.5, 0.5, 0);
    CHECK(l.scene.camera.near_clip == 0.25);
    CHECK(l.scene.camera.far_clip == 50.0);
  }
  SECTION("the point one unit ahead, read as a direction from the origin") {
    // Camera at (3,0,0) looking along -X: one unit ahead is (2,0,0).
    d.nodes += node("<translate>3 0 0</translate><rotate>0 1 0 90</rotate>", "<instance_camera url=\"#cam\"/>");
    const Loaded l = load(d);
    check_vec(l.scene.camera.position, 0.5 + dist, 0.5, 0);
    check_vec(l.scene.camera.axis_z, 1, 0, 0);  // looks along -X
  }
  SECTION("the first camera in document order is used") {
    d.cameras += camera("cam2", "<xfov>80</xfov>");
    d.nodes += node("", node("<translate>0 0 -5</translate>", "<instance_camera url=\"#cam2\"/>")) +
               node("<translate>0 0 5</translate>", "<instance_camera url=\"#cam\"/>");
    const Loaded l = load(d);
    check_vec(l.scene.camera.position, 0.5, 0.5, -dist);
    CHECK(l.scene.camera.hfov_deg == Approx(80));
  }
}

TEST_CASE("no camera: documented fallback with a warning", "[collada][camera]") {
  const Loaded l = load(triangle_doc());
  CHECK(has_warning(l, "<visual_scene id=\"Scene\">", "no camera"));
  check_vec(l.scene.camera.position, 0.5, 0.5, 1.5 * std::sqrt(2.0));
  check_vec(l.scene.camera.axis_z, 0, 0, 1);  // looking toward -Z
  CHECK(l.scene.camera.hfov_deg == Approx(50));
  CHECK(l.scene.camera.vfov_deg == Approx(deg(2 * std::atan(std::tan(rad(25)) * 0.75))));
  CHECK(l.scene.camera.near_clip == 0.001);
  CHECK(l.scene.camera.far_clip == 1000.0);
}

// ---- Bad input -----------------------------------------------------------------------------

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

TEST_CASE("material and light colours need the right number of numbers", "[collada][errors]") {
  Doc d = triangle_doc();
  d.materials = material("mat", "fx");
  d.nodes = node("", instance_geometry("tri", {{"s", "mat"}}));
  SECTION("profile_COMMON diffuse colour") {
    d.effects = effect_common("fx", "phong", "0.5 0.5");
    CHECK_THAT(error_of(d), Contains("<color>") && Contains("found 2"));
  }
  SECTION("CGL radiance") {
    d.effects = effect_cgl("fx", "<emission><radiance>1 1</radiance></emission>");
    CHECK_THAT(error_of(d), Contains("<radiance>") && Contains("found 2"));
  }
  SECTION("CGL eta") {
    d.effects = effect_cgl("fx", "<microfacet><alpha>0.5</alpha><eta>1 1 1 1</eta></microfacet>");
    CHECK_THAT(error_of(d), Contains("<eta>") && Contains("found 4"));
  }
  SECTION("negative colour") {
    d.effects = effect_common("fx", "lambert", "0.5 -0.5 0.5 1");
    CHECK_THAT(error_of(d), Contains("<color>") && Contains("negative"));
  }
  SECTION("light colour") {
    d.effects = effect_common("fx", "phong", "0.5 0.5 0.5");
    d.lights = light("L", "<point><color>1 1 1 1 1</color></point>");
    d.nodes += node("", instance_light("L"));
    CHECK_THAT(error_of(d), Contains("<color>") && Contains("found 5"));
  }
}

TEST_CASE("a scene without triangles or spheres is an error", "[collada][errors]") {
  Doc d;
  d.cameras = camera("cam", "<xfov>40</xfov>");
  d.nodes = node("<translate>0 0 5</translate>", "<instance_camera url=\"#cam\"/>");
  CHECK_THAT(error_of(d), Contains("<visual_scene id=\"Scene\">") && Contains("no triangles or spheres"));
}

TEST_CASE("warnings are one line and start with the file's path", "[collada]") {
  Doc d = triangle_doc();
  d.lights = light("S", "<spot><color>1 1 1</color></spot>");
  d.nodes += node("", instance_light("S"));
  const Loaded l = load(d);
  REQUIRE(l.warnings.size() == 2);  // the spot light and the missing camera
  for (const std::string& w : l.warnings) {
    CHECK_THAT(w, StartsWith(l.path + ": <"));
    CHECK(w.find('\n') == std::string::npos);
  }
}

// ---- Hostile and sloppy files ---------------------------------------------------------

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

TEST_CASE("a misspelt element inside a node is reported with a warning naming it and its line", "[collada]") {
  Doc d = triangle_doc();
  d.nodes = node("", instance_geometry("tri")) +
            "\n<node id=\"lost\">\n<instance_geometery url=\"#tri\"/>\n</node>\n";
  const Loaded l = load(d);
  CHECK(l.scene.triangles.size() == 1);
  CHECK(has_warning(l, "<instance_geometery> (line ", "<node id=\"lost\">"));
  CHECK(has_warning(l, "<instance_geometery>", "ignored"));
}

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

TEST_CASE("numbers that overflow single precision are refused, not turned into infinity (fuzz findings)",
          "[collada][errors]") {
  SECTION("a sphere so large that the camera would stand at infinity") {
    Doc d;
    d.geometries = "<geometry id=\"ball\"><extra><technique profile=\"CGL\"><sphere><radius>3.4e38</radius>"
                   "</sphere></technique></extra></geometry>";
    d.nodes = node("", instance_geometry("ball"));
    CHECK_THAT(error_of(d), Contains("<visual_scene id=\"Scene\">") && Contains("too large for single-precision"));
  }
  SECTION("a light colour beyond float range") {
    Doc d = triangle_doc();
    d.lights = light("L", "<point><color>3.5e38 5 5</color></point>");
    d.nodes += node("", instance_light("L"));
    CHECK_THAT(error_of(d), Contains("<color>") && Contains("too large for single precision"));
  }
  SECTION("an attenuation beyond float range") {
    Doc d = triangle_doc();
    d.lights = light("L", "<point><color>1 1 1</color><constant_attenuation>1e39</constant_attenuation></point>");
    d.nodes += node("", instance_light("L"));
    CHECK_THAT(error_of(d), Contains("<constant_attenuation>") && Contains("too large"));
  }
}

TEST_CASE("an aspect ratio that leaves no field of view is refused (fuzz finding)", "[collada][camera][errors]") {
  for (const char* aspect : {"1e-320", "1e-300"}) {
    SECTION(aspect) {
      Doc d = triangle_doc();
      d.cameras = camera("cam", std::string("<xfov>49.13</xfov><aspect_ratio>") + aspect + "</aspect_ratio>");
      d.nodes += node("<translate>0 0 5</translate>", "<instance_camera url=\"#cam\"/>");
      CHECK_THAT(error_of(d), Contains("<perspective>") && Contains("field of view"));
    }
  }
  SECTION("a field of view too narrow to fit the frame") {
    Doc d = triangle_doc();
    d.cameras = camera("cam", "<xfov>1e-320</xfov><yfov>1e-320</yfov>");
    d.nodes += node("<translate>0 0 5</translate>", "<instance_camera url=\"#cam\"/>");
    CHECK_THAT(error_of(d), Contains("<perspective>") && Contains("field of view"));
  }
}
