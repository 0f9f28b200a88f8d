// Building a mesh's renderable triangles from position indices: the used
// positions renumbered and moved to world space, zero-area triangles
// dropped, smooth normals from area-weighted face normals, and the course's
// reversal of meshes made only of boundary vertices. Needs no XML: the
// primitive readers (primitive_lists.h) produce its input.
#pragma once
#include <array>
#include <cstddef>
#include <optional>
#include <vector>

#include "common/mat4.h"
#include "common/scene.h"
#include "common/vec3.h"

namespace pt::collada {

// A triangle as three indices into its mesh's positions.
using TriangleIndices = std::array<int, 3>;

// A mesh's triangles as its primitive lists give them.
struct MeshTriangles {
  std::vector<TriangleIndices> corners;
  std::vector<int> materials;  // the scene material of each triangle
};

// Renumbers the positions that `tris` uses as 0, 1, 2, ... in the order of
// their indices and rewrites `tris` with the new numbers. Returns the old
// index of each new number. Every index must be below `position_count`.
std::vector<int> renumber_used_positions(std::vector<TriangleIndices>& tris, size_t position_count);

// A position that leaves single precision's range in world space.
struct PositionOverflow {
  size_t index;  // in the file's positions
  Vec3d point;   // its world-space place, in double
};

// World-space positions, stored in float as the renderer will see them, of
// the file positions `used` (`xyz` holds 3 numbers per file position).
// Returns the first one that is not finite in float, if any.
std::optional<PositionOverflow> world_positions(const std::vector<double>& xyz, const std::vector<int>& used,
                                                const Mat4& world, std::vector<Vec3>* out);

// Whether every vertex used by a non-degenerate triangle lies on a
// boundary edge (an edge of exactly one triangle). `face` holds each
// triangle's face normal; a zero one marks a degenerate triangle.
bool all_vertices_on_boundary(const std::vector<TriangleIndices>& tris, const std::vector<Vec3d>& face);

// Appends the mesh's triangles with area-weighted smooth normals to `out`,
// dropping zero-area ones; returns how many were dropped. Meshes made only
// of boundary vertices are reversed, as the course's half-edge code does.
size_t add_mesh_triangles(const std::vector<Vec3>& positions, const MeshTriangles& mesh,
                          std::vector<Triangle>& out);

}  // namespace pt::collada
