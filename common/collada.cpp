// Loading a COLLADA scene file: the driver. The conventions implemented are
// documented in docs/scene-format.md; the parts live in collada/:
//   messages       errors and warnings naming the file and element
//   xml_values     numbers, lists, colours and counts from XML text
//   document       the parsed file, its ids, up axis and visual scene
//   node_walk      the scene graph walk with world transforms
//   geometry_reader, primitive_lists, mesh_sources, mesh_builder
//                  meshes and spheres
//   material_reader, light_reader, camera_reader
//                  materials, lights and the camera
//
// The document is parsed once, every element with an id is indexed, and the
// chosen <visual_scene> is walked depth-first in document order with the
// accumulated world transform. Geometry, lights and the camera are converted
// to world space (Y up) as they are met; materials are created on first use.
// The camera is placed last, from the bounds of all geometry.
#include "common/collada.h"

#include <new>

#include "common/collada/camera_reader.h"
#include "common/collada/document.h"
#include "common/collada/geometry_reader.h"
#include "common/collada/material_reader.h"
#include "common/collada/messages.h"
#include "common/collada/node_walk.h"

namespace pt {

namespace {

Scene load(const std::string& path, std::vector<std::string>* warnings) {
  collada::Messages msg(path, warnings);
  collada::Document doc(msg);
  doc.read(path);
  const Mat4 up_axis = doc.up_axis_transform();
  const tinyxml2::XMLElement* vscene = doc.visual_scene();
  Scene scene;
  scene.source = path;
  collada::MaterialReader materials(msg, doc, scene.materials);
  collada::GeometryReader geometry(msg, doc, materials, scene);
  collada::CameraReader camera(msg, doc);
  collada::NodeWalk(msg, doc, geometry, camera, scene).walk(vscene, up_axis);
  if (scene.triangles.empty() && scene.spheres.empty()) msg.fail(vscene, "no triangles or spheres in the scene");
  camera.finish(vscene, scene);
  return scene;
}

}  // namespace

Scene load_collada(const std::string& path, std::vector<std::string>* warnings) {
  try {
    return load(path, warnings);
  } catch (const SceneError&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw SceneError(path + ": out of memory while loading the scene");
  } catch (const std::exception& e) {
    throw SceneError(collada::one_line(path + ": " + e.what()));
  }
}

}  // namespace pt
