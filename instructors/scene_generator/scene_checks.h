// The checks every scene passes before it is written, and the one-line
// summary make_scenes prints for it.
#pragma once
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "instructors/scene_generator/collada_writer.h"
#include "instructors/scene_generator/mesh_tools.h"
#include "instructors/scene_generator/scene_model.h"
#include "instructors/scene_generator/scene_parts.h"

namespace scenegen {

// ---------------------------------------------------------------------------
// Checks and the summary line

// The course's camera position, computed from what is written: the node
// matrix in file coordinates mapped back to world space.
inline V3 course_camera_position(const Scene& s) {
  const auto m = node_matrix(s.camera);
  const V3 front_file{m[3] - m[2], m[7] - m[6], m[11] - m[10]};  // M (0,0,-1,1)
  const V3 c_dir = normalize(zup_to_world(front_file));
  const Bounds b = scene_bounds(s);
  return b.center() + (1.5 * length(b.extent())) * c_dir;
}

// Moves every mesh vertex to exactly the position its printed coordinates
// give back, so that the checks below see what a reader of the file sees.
// (Printing the snapped numbers again gives the same text.)
inline void snap_to_file_precision(Scene& s) {
  auto back = [](double v) { return std::strtod(num(v).c_str(), nullptr); };
  for (Mesh& m : s.meshes)
    for (V3& p : m.vertices) {
      const V3 f = world_to_zup(p);
      p = zup_to_world(V3{back(f.x), back(f.y), back(f.z)});
    }
}

// Checks each mesh as a reader will load it (positions rounded to float):
// no zero-area triangle, and closed meshes closed, consistently wound and
// enclosing positive volume.
inline void validate_mesh(const Scene& s, const Mesh& m) {
  const std::string where = s.file + ": mesh '" + m.name + "'";
  std::vector<V3> f(m.vertices.size());
  for (size_t i = 0; i < f.size(); ++i) {
    const V3 w = m.vertices[i];
    f[i] = V3{double(float(w.x)), double(float(w.y)), double(float(w.z))};
  }
  for (const auto& t : m.triangles)
    if (length(cross(f[size_t(t[1])] - f[size_t(t[0])], f[size_t(t[2])] - f[size_t(t[0])])) == 0)
      throw std::logic_error(where + ": a triangle has zero area after rounding");
  if (m.closed) {
    IndexedMesh im{m.vertices, m.triangles};
    const Topology topo = topology(im);
    if (!topo.closed()) throw std::logic_error(where + ": is marked closed but is not");
    if (signed_volume(im) <= 0) throw std::logic_error(where + ": is not wound outward");
  }
}

inline void validate(const Scene& s) {
  if (s.purpose.find("--") != std::string::npos)
    throw std::logic_error(s.file + ": purpose text may not contain \"--\" (XML comment)");
  for (const Mesh& m : s.meshes)
    for (const auto& t : m.triangles)
      for (int i : t)
        if (i < 0 || static_cast<size_t>(i) >= m.vertices.size())
          throw std::logic_error(s.file + ": mesh '" + m.name + "' has a bad vertex index");
  auto has_material = [&](const std::string& name) {
    for (const Material& m : s.materials)
      if (m.name == name) return true;
    return false;
  };
  for (const Mesh& m : s.meshes)
    if (!has_material(m.material)) throw std::logic_error(s.file + ": unknown material " + m.material);
  for (const Sphere& sp : s.spheres)
    if (!has_material(sp.material)) throw std::logic_error(s.file + ": unknown material " + sp.material);
  for (const Mesh& m : s.meshes) validate_mesh(s, m);
}

inline std::string light_summary(const Scene& s) {
  std::string r;
  for (const Light& l : s.lights) {
    if (!r.empty()) r += ", ";
    switch (l.kind) {
      case LightKind::Point: r += "point"; break;
      case LightKind::Area: r += "area"; break;
      case LightKind::Ambient: r += "ambient"; break;
      case LightKind::Directional: r += "directional"; break;
    }
  }
  return r;
}

inline std::string summary(const Scene& s) {
  const V3 c = course_camera_position(s);
  std::ostringstream o;
  o << s.file << ": " << s.triangle_count() << " triangles, " << s.spheres.size() << " sphere(s), "
    << s.lights.size() << " light(s) (" << light_summary(s) << "); course camera at (" << num(c.x)
    << ", " << num(c.y) << ", " << num(c.z) << ")";
  return o.str();
}

}  // namespace scenegen
