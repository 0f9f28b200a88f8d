// Small COLLADA documents for the loader's tests (see collada_documents.h).
#include "tests/common/collada_documents.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <sstream>

#include "tests/support.h"

namespace pt::test::dae {

using Catch::Matchers::StartsWith;

// ---- Building documents ---------------------------------------------------

std::string list(const std::vector<double>& v) {
  std::ostringstream s;
  s.precision(17);
  for (size_t i = 0; i < v.size(); ++i) s << (i ? " " : "") << v[i];
  return s.str();
}

std::string mesh(const std::string& id, const std::string& xyz, size_t count, const std::string& prims,
                 const std::string& extra_sources) {
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
                     const std::string& material) {
  std::istringstream vs(vcount);
  int n = 0, c = 0;
  while (vs >> c) ++n;
  return "<polylist" + (material.empty() ? "" : " material=\"" + material + "\"") + " count=\"" +
         std::to_string(n) + "\">" + vertex_input(id) + "<vcount>" + vcount + "</vcount><p>" + p +
         "</p></polylist>";
}

std::string triangles(const std::string& id, int count, const std::string& p, const std::string& material) {
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
                              const std::vector<std::pair<std::string, std::string>>& symbol_target) {
  return "<instance_geometry url=\"#" + id + "\">" + bind(symbol_target) + "</instance_geometry>";
}

std::string node(const std::string& transforms, const std::string& content, const std::string& id) {
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

std::string light(const std::string& id, const std::string& common, const std::string& cgl) {
  std::string s = "<light id=\"" + id + "\">";
  if (!common.empty()) s += "<technique_common>" + common + "</technique_common>";
  if (!cgl.empty()) s += "<extra><technique profile=\"CGL\">" + cgl + "</technique></extra>";
  return s + "</light>";
}

std::string instance_light(const std::string& id) { return "<instance_light url=\"#" + id + "\"/>"; }

std::string Doc::str() const {
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

Doc triangle_doc(const std::string& transforms) {
  Doc d;
  d.geometries = mesh("tri", {0, 0, 0, 1, 0, 0, 0, 1, 0}, polylist("tri", "3", "0 1 2"));
  d.nodes = node(transforms, instance_geometry("tri"));
  return d;
}

// ---- Loading ---------------------------------------------------------------------

Loaded load(const std::string& text) {
  pt::test::TempDir dir;
  Loaded r;
  r.path = dir.file("scene.dae");
  pt::test::write_text(r.path, text);
  r.scene = pt::load_collada(r.path, &r.warnings);
  return r;
}

Loaded load(const Doc& d) { return load(d.str()); }

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

bool has_warning(const Loaded& l, const std::string& a, const std::string& b) {
  for (const std::string& w : l.warnings) {
    if (w.rfind(l.path + ": ", 0) != 0 || w.find('\n') != std::string::npos) continue;
    if (w.find(a) != std::string::npos && (b.empty() || w.find(b) != std::string::npos)) return true;
  }
  return false;
}

void check_vec(const pt::Vec3& v, double x, double y, double z, double eps) {
  INFO("got (" << v.x << ", " << v.y << ", " << v.z << "), want (" << x << ", " << y << ", " << z << ")");
  CHECK(v.x == Approx(x).margin(eps));
  CHECK(v.y == Approx(y).margin(eps));
  CHECK(v.z == Approx(z).margin(eps));
}

void check_vec(const pt::Vec3d& v, double x, double y, double z, double eps) {
  check_vec(pt::Vec3(v), x, y, z, std::max(eps, 1e-6));
}

}  // namespace pt::test::dae
