// Small COLLADA documents written by hand for the loader's tests, and
// loading them: the builders (meshes, primitive lists, nodes, cameras,
// effects, materials, lights), a whole document (Doc), the scene or the
// error it loads to, and checks of warnings and vectors.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "common/collada.h"

namespace pt::test::dae {

// ---- Building documents ---------------------------------------------------

// Numbers separated by spaces, with every digit a double holds.
std::string list(const std::vector<double>& v);

// A <geometry> holding a mesh with positions `xyz` and primitive lists
// `prims` (whose VERTEX input is "#ID-vertices").
std::string mesh(const std::string& id, const std::string& xyz, size_t count, const std::string& prims,
                 const std::string& extra_sources = "");
std::string mesh(const std::string& id, const std::vector<double>& xyz, const std::string& prims);

std::string vertex_input(const std::string& id);
std::string polylist(const std::string& id, const std::string& vcount, const std::string& p,
                     const std::string& material = "");
std::string triangles(const std::string& id, int count, const std::string& p, const std::string& material = "");
std::string bind(const std::vector<std::pair<std::string, std::string>>& symbol_target);
std::string instance_geometry(const std::string& id,
                              const std::vector<std::pair<std::string, std::string>>& symbol_target = {});
std::string node(const std::string& transforms, const std::string& content, const std::string& id = "");
std::string camera(const std::string& id, const std::string& perspective);
std::string effect_common(const std::string& id, const std::string& model, const std::string& color);
std::string effect_cgl(const std::string& id, const std::string& cgl);
std::string material(const std::string& id, const std::string& effect);
std::string light(const std::string& id, const std::string& common, const std::string& cgl = "");
std::string instance_light(const std::string& id);

// A whole document, its libraries filled in by the tests.
struct Doc {
  std::string up_axis = "Y_UP";  // empty: no <up_axis>
  std::string cameras, lights, effects, materials, geometries, library_nodes;
  std::string nodes;         // contents of <visual_scene id="Scene">
  std::string more_scenes;   // further <visual_scene> elements
  std::string scene = "<scene><instance_visual_scene url=\"#Scene\"/></scene>";

  std::string str() const;
};

// A document with one triangle (0,0,0) (1,0,0) (0,1,0) in geometry "tri"
// under a node with `transforms`.
Doc triangle_doc(const std::string& transforms = "");

// ---- Loading ---------------------------------------------------------------------

struct Loaded {
  pt::Scene scene;
  std::vector<std::string> warnings;
  std::string path;
};

Loaded load(const std::string& text);
Loaded load(const Doc& d);

// The message of the SceneError that loading `text` throws. Checks the
// message is one line starting with the file's path.
std::string error_of(const std::string& text);
std::string error_of(const Doc& d);

// Whether a warning (one line, starting with the file's path) contains `a`
// and, when given, `b`.
bool has_warning(const Loaded& l, const std::string& a, const std::string& b = "");

void check_vec(const pt::Vec3& v, double x, double y, double z, double eps = 1e-5);
void check_vec(const pt::Vec3d& v, double x, double y, double z, double eps = 1e-9);

}  // namespace pt::test::dae
