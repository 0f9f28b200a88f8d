// The primitive readers: a mesh's <triangles>, <polylist> and <polygons>
// read into position-index triangles (polygons fan-triangulated), each with
// its material. Every index is checked against the element count of the
// source its input names, by one check shared by the three kinds.
#pragma once
#include <cstddef>
#include <functional>

#include "common/collada/document.h"
#include "common/collada/mesh_builder.h"
#include "common/collada/mesh_sources.h"
#include "common/collada/messages.h"

namespace pt::collada {

// What reading a mesh's primitive lists needs.
struct PrimitiveListContext {
  Messages& msg;
  const Document& doc;
  MeshSources& sources;
  size_t scene_primitives;  // triangles and spheres already in the scene
  // The scene material for a list's material="symbol" (null when absent).
  std::function<int(const char* symbol)> material_of;
};

// A mesh's primitive lists as read so far.
struct MeshPrimitives {
  const XMLElement* position_source = nullptr;  // the <source> every VERTEX input names
  MeshTriangles triangles;
};

// Appends the triangles of `prim` (a <triangles>, <polylist> or <polygons>)
// to `mesh`.
void read_primitive_list(const XMLElement* prim, const PrimitiveListContext& ctx, MeshPrimitives& mesh);

// Fails naming `e` when `more` triangles or spheres on top of the scene's
// `have` would pass kMaxScenePrimitives.
void check_primitive_limit(const Messages& msg, const XMLElement* e, size_t have, size_t more);

}  // namespace pt::collada
