// Writes a scenegen::Scene as COLLADA 1.4.1 in the course's dialect (Z_UP,
// <matrix> nodes, <polylist> meshes, CGL extensions). The output depends only
// on the scene: numbers are printed with a fixed "%.6g" format in the C
// locale, element order is fixed and nothing time- or host-dependent is
// written, so the same scene always gives the same bytes.
#pragma once
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "instructors/scene_generator/scene_model.h"

namespace scenegen {

// Compact fixed formatting: 6 significant digits, no "-0", no 1e-17 noise.
inline std::string num(double v) {
  if (std::fabs(v) < 5e-13) v = 0.0;
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

inline std::string nums(const std::vector<double>& v) {
  std::string s;
  for (size_t i = 0; i < v.size(); ++i) {
    if (i) s += ' ';
    s += num(v[i]);
  }
  return s;
}

inline std::string rgb(const Rgb& c) { return nums({c[0], c[1], c[2]}); }
inline std::string rgba(const Rgb& c) { return nums({c[0], c[1], c[2], 1.0}); }

inline std::string xml_escape(const std::string& s) {
  std::string r;
  for (char ch : s) {
    switch (ch) {
      case '&': r += "&amp;"; break;
      case '<': r += "&lt;"; break;
      case '>': r += "&gt;"; break;
      case '"': r += "&quot;"; break;
      default: r += ch;
    }
  }
  return r;
}

// A minimal indenting XML emitter (two spaces per level, '\n' line ends).
class XmlOut {
 public:
  using Attrs = std::vector<std::pair<std::string, std::string>>;

  void raw_line(const std::string& s) { out_ << s << '\n'; }
  void open(const std::string& tag, const Attrs& attrs = {}) {
    indent();
    out_ << '<' << tag << attr_string(attrs) << ">\n";
    stack_.push_back(tag);
  }
  void close() {
    const std::string tag = stack_.back();
    stack_.pop_back();
    indent();
    out_ << "</" << tag << ">\n";
  }
  void leaf(const std::string& tag, const std::string& text, const Attrs& attrs = {}) {
    indent();
    out_ << '<' << tag << attr_string(attrs) << '>' << xml_escape(text) << "</" << tag << ">\n";
  }
  void empty(const std::string& tag, const Attrs& attrs = {}) {
    indent();
    out_ << '<' << tag << attr_string(attrs) << "/>\n";
  }
  std::string str() const { return out_.str(); }
  bool balanced() const { return stack_.empty(); }

 private:
  void indent() { out_ << std::string(2 * stack_.size(), ' '); }
  static std::string attr_string(const Attrs& attrs) {
    std::string s;
    for (const auto& a : attrs) s += ' ' + a.first + "=\"" + xml_escape(a.second) + '"';
    return s;
  }
  std::ostringstream out_;
  std::vector<std::string> stack_;
};

inline std::string effect_id(const std::string& m) { return m + "-effect"; }
inline std::string material_id(const std::string& m) { return m + "-material"; }

inline void write_asset(XmlOut& x) {
  x.open("asset");
  x.open("contributor");
  x.leaf("author", "cs184_pathtracer project");
  x.leaf("authoring_tool", "cs184_pathtracer make_scenes (instructors/scene_generator/make_scenes.cpp)");
  x.close();
  x.empty("unit", {{"name", "meter"}, {"meter", "1"}});
  x.leaf("up_axis", "Z_UP");
  x.close();
}

inline void write_cameras(XmlOut& x) {
  x.open("library_cameras");
  x.open("camera", {{"id", "Camera-camera"}, {"name", "Camera"}});
  x.open("optics");
  x.open("technique_common");
  x.open("perspective");
  x.leaf("xfov", "49.13434", {{"sid", "xfov"}});
  x.leaf("aspect_ratio", "1.333333");
  x.leaf("znear", "0.1", {{"sid", "znear"}});
  x.leaf("zfar", "100", {{"sid", "zfar"}});
  x.close();
  x.close();
  x.close();
  x.close();
  x.close();
}

inline void write_lights(XmlOut& x, const Scene& s) {
  x.open("library_lights");
  for (const Light& l : s.lights) {
    x.open("light", {{"id", l.name + "-light"}, {"name", l.name}});
    x.open("technique_common");
    if (l.kind == LightKind::Ambient) {
      x.open("ambient");
      x.leaf("color", rgb(l.color), {{"sid", "color"}});
      x.close();
    } else if (l.kind == LightKind::Directional) {
      x.open("directional");
      x.leaf("color", rgb(l.color), {{"sid", "color"}});
      x.close();
    } else {
      // Area lights carry a point-light fallback here (the schema requires a
      // technique_common); CGL-aware readers use the <extra> below instead.
      x.open("point");
      x.leaf("color", rgb(l.color), {{"sid", "color"}});
      x.leaf("constant_attenuation", num(l.constant_attenuation));
      x.leaf("linear_attenuation", num(l.linear_attenuation));
      x.leaf("quadratic_attenuation", num(l.quadratic_attenuation));
      x.close();
    }
    x.close();
    if (l.kind == LightKind::Area) {
      x.open("extra");
      x.open("technique", {{"profile", "CGL"}});
      x.open("area");
      x.leaf("color", rgb(l.color), {{"sid", "color"}});
      x.close();
      x.close();
      x.close();
    }
    x.close();
  }
  x.close();
}

inline void write_effects(XmlOut& x, const Scene& s) {
  x.open("library_effects");
  for (const Material& m : s.materials) {
    x.open("effect", {{"id", effect_id(m.name)}});
    x.open("profile_COMMON");
    x.open("technique", {{"sid", "common"}});
    x.open("phong");
    x.open("emission");
    x.leaf("color", rgba({0, 0, 0}), {{"sid", "emission"}});
    x.close();
    x.open("diffuse");
    x.leaf("color", rgba(m.diffuse), {{"sid", "diffuse"}});
    x.close();
    x.close();
    x.close();
    x.close();
    if (m.kind != MaterialKind::Diffuse) {
      x.open("extra");
      x.open("technique", {{"profile", "CGL"}});
      switch (m.kind) {
        case MaterialKind::Emission:
          x.open("emission");
          x.leaf("radiance", rgb(m.emission));
          x.close();
          break;
        case MaterialKind::Mirror:
          x.open("mirror");
          x.leaf("reflectance", rgb(m.reflectance));
          x.close();
          break;
        case MaterialKind::Glass:
          x.open("glass");
          x.leaf("reflectance", rgb(m.reflectance));
          x.leaf("transmittance", rgb(m.transmittance));
          x.leaf("roughness", num(m.roughness));
          x.leaf("ior", num(m.ior));
          x.close();
          break;
        case MaterialKind::Microfacet:
          x.open("microfacet");
          x.leaf("alpha", num(m.alpha));
          x.leaf("eta", rgb(m.eta));
          x.leaf("k", rgb(m.k));
          x.close();
          break;
        case MaterialKind::Diffuse:
          break;
      }
      x.close();
      x.close();
    }
    x.close();
  }
  x.close();
}

inline void write_materials(XmlOut& x, const Scene& s) {
  x.open("library_materials");
  for (const Material& m : s.materials) {
    x.open("material", {{"id", material_id(m.name)}, {"name", m.name}});
    x.empty("instance_effect", {{"url", "#" + effect_id(m.name)}});
    x.close();
  }
  x.close();
}

inline void write_geometries(XmlOut& x, const Scene& s) {
  x.open("library_geometries");
  for (const Mesh& m : s.meshes) {
    const std::string gid = m.name + "-mesh";
    x.open("geometry", {{"id", gid}, {"name", m.name}});
    x.open("mesh");
    x.open("source", {{"id", gid + "-positions"}});
    std::vector<double> p;
    for (const V3& w : m.vertices) {
      const V3 f = world_to_zup(w);
      p.insert(p.end(), {f.x, f.y, f.z});
    }
    x.leaf("float_array", nums(p),
           {{"id", gid + "-positions-array"}, {"count", std::to_string(p.size())}});
    x.open("technique_common");
    x.open("accessor", {{"source", "#" + gid + "-positions-array"},
                        {"count", std::to_string(m.vertices.size())},
                        {"stride", "3"}});
    for (const char* axis : {"X", "Y", "Z"}) x.empty("param", {{"name", axis}, {"type", "float"}});
    x.close();
    x.close();
    x.close();
    x.open("vertices", {{"id", gid + "-vertices"}});
    x.empty("input", {{"semantic", "POSITION"}, {"source", "#" + gid + "-positions"}});
    x.close();
    x.open("polylist", {{"material", material_id(m.material)},
                        {"count", std::to_string(m.triangles.size())}});
    x.empty("input", {{"semantic", "VERTEX"}, {"source", "#" + gid + "-vertices"}, {"offset", "0"}});
    std::string vcount, idx;
    for (size_t i = 0; i < m.triangles.size(); ++i) {
      vcount += (i ? " 3" : "3");
      for (int k = 0; k < 3; ++k) {
        if (!idx.empty()) idx += ' ';
        idx += std::to_string(m.triangles[i][k]);
      }
    }
    x.leaf("vcount", vcount);
    x.leaf("p", idx);
    x.close();
    x.close();
    x.close();
  }
  for (const Sphere& sp : s.spheres) {
    x.open("geometry", {{"id", sp.name + "-sphere"}, {"name", sp.name}});
    x.open("extra");
    x.open("technique", {{"profile", "CGL"}});
    x.open("sphere");
    x.leaf("radius", num(sp.radius));
    x.close();
    x.close();
    x.close();
    x.close();
  }
  x.close();
}

inline void write_matrix(XmlOut& x, const Xform& w) {
  const auto m = node_matrix(w);
  x.leaf("matrix", nums(std::vector<double>(m.begin(), m.end())), {{"sid", "transform"}});
}

inline void write_geometry_instance(XmlOut& x, const std::string& url, const std::string& material) {
  x.open("instance_geometry", {{"url", url}});
  x.open("bind_material");
  x.open("technique_common");
  x.empty("instance_material", {{"symbol", material_id(material)}, {"target", "#" + material_id(material)}});
  x.close();
  x.close();
  x.close();
}

inline void write_visual_scene(XmlOut& x, const Scene& s) {
  x.open("library_visual_scenes");
  x.open("visual_scene", {{"id", "Scene"}, {"name", "Scene"}});

  x.open("node", {{"id", "Camera"}, {"name", "Camera"}, {"type", "NODE"}});
  write_matrix(x, s.camera);
  x.empty("instance_camera", {{"url", "#Camera-camera"}});
  x.close();

  for (const Light& l : s.lights) {
    x.open("node", {{"id", l.name}, {"name", l.name}, {"type", "NODE"}});
    write_matrix(x, l.node);
    x.empty("instance_light", {{"url", "#" + l.name + "-light"}});
    x.close();
  }
  for (const Mesh& m : s.meshes) {
    // Vertices are already in file coordinates: the node adds nothing.
    x.open("node", {{"id", m.name}, {"name", m.name}, {"type", "NODE"}});
    write_matrix(x, zup_frame({0, 0, 0}));
    write_geometry_instance(x, "#" + m.name + "-mesh", m.material);
    x.close();
  }
  for (const Sphere& sp : s.spheres) {
    x.open("node", {{"id", sp.name}, {"name", sp.name}, {"type", "NODE"}});
    write_matrix(x, zup_frame(sp.center));
    write_geometry_instance(x, "#" + sp.name + "-sphere", sp.material);
    x.close();
  }

  x.close();
  x.close();
}

inline std::string write_collada(const Scene& s) {
  XmlOut x;
  x.raw_line("<?xml version=\"1.0\" encoding=\"utf-8\"?>");
  x.raw_line("<!-- Generated by instructors/scene_generator/make_scenes.cpp; do not edit by hand."
             " Change the generator and regenerate (see scenes/README.md). -->");
  x.raw_line("<!-- " + s.file + ": " + s.purpose + " -->");
  x.open("COLLADA", {{"xmlns", "http://www.collada.org/2005/11/COLLADASchema"}, {"version", "1.4.1"}});
  write_asset(x);
  write_cameras(x);
  write_lights(x, s);
  write_effects(x, s);
  write_materials(x, s);
  write_geometries(x, s);
  write_visual_scene(x, s);
  x.open("scene");
  x.empty("instance_visual_scene", {{"url", "#Scene"}});
  x.close();
  x.close();
  return x.str();
}

}  // namespace scenegen
