// Geometry: an <instance_geometry>'s <geometry>, a <mesh> (its primitive
// lists read, then built into world-space triangles) or a CGL <sphere>,
// added to the scene with the materials the instance binds.
#pragma once
#include <vector>

#include "common/collada/document.h"
#include "common/mat4.h"
#include "common/collada/material_reader.h"
#include "common/collada/mesh_sources.h"
#include "common/collada/messages.h"
#include "common/scene.h"

namespace pt::collada {

class GeometryReader {
 public:
  GeometryReader(Messages& msg, const Document& doc, MaterialReader& materials, Scene& scene)
      : msg_(msg), doc_(doc), materials_(materials), scene_(scene), sources_(msg, doc) {}

  // Adds the geometry `inst` places with the node transform `world`.
  void add(const XMLElement* inst, const Mat4& world);

 private:
  void add_mesh(const XMLElement* geom, const XMLElement* mesh, const std::vector<InstanceMaterial>& bound,
                const Mat4& world);
  void add_sphere(const XMLElement* sphere, const std::vector<InstanceMaterial>& bound, const Mat4& world);

  Messages& msg_;
  const Document& doc_;
  MaterialReader& materials_;
  Scene& scene_;
  MeshSources sources_;
};

}  // namespace pt::collada
