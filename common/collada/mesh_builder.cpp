// Building a mesh's renderable triangles (see mesh_builder.h).
#include "common/collada/mesh_builder.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "common/collada.h"

namespace pt::collada {

namespace {

// Per position, the sum of the (area-weighted) cross products of the
// triangles using it; per triangle, its face normal (zero when degenerate).
struct NormalSums {
  std::vector<Vec3d> vertex;
  std::vector<Vec3d> face;
  size_t degenerate = 0;
};

NormalSums sum_normals(const std::vector<Vec3>& wp, const std::vector<TriangleIndices>& tris) {
  NormalSums s;
  s.vertex.assign(wp.size(), Vec3d(0.0));
  s.face.resize(tris.size());
  for (size_t t = 0; t < tris.size(); ++t) {
    const Vec3d a(wp[size_t(tris[t][0])]), b(wp[size_t(tris[t][1])]), c(wp[size_t(tris[t][2])]);
    const Vec3d n = cross(b - a, c - a);
    s.face[t] = n;
    if (norm2(n) == 0) {
      ++s.degenerate;
      continue;
    }
    for (int k = 0; k < 3; ++k) s.vertex[size_t(tris[t][size_t(k)])] += n;
  }
  return s;
}

}  // namespace

std::vector<int> renumber_used_positions(std::vector<TriangleIndices>& tris, size_t position_count) {
  // Only the positions the triangles use are kept: an instance costs its
  // triangles, not the whole position array (which matters when a large
  // array is instanced many times). A dense table when the array is not
  // much larger than the triangles' corners, else a sorted list.
  std::vector<int> used;
  if (position_count <= 12 * tris.size()) {
    std::vector<int> number(position_count, -1);
    for (const auto& t : tris)
      for (int v : t) number[size_t(v)] = 0;
    for (size_t i = 0; i < number.size(); ++i)
      if (number[i] == 0) {
        number[i] = int(used.size());
        used.push_back(int(i));
      }
    for (auto& t : tris)
      for (int& v : t) v = number[size_t(v)];
  } else {
    used.reserve(3 * tris.size());
    for (const auto& t : tris) used.insert(used.end(), t.begin(), t.end());
    std::sort(used.begin(), used.end());
    used.erase(std::unique(used.begin(), used.end()), used.end());
    for (auto& t : tris)
      for (int& v : t) v = int(std::lower_bound(used.begin(), used.end(), v) - used.begin());
  }
  return used;
}

std::optional<PositionOverflow> world_positions(const std::vector<double>& xyz, const std::vector<int>& used,
                                                const Mat4& world, std::vector<Vec3>* out) {
  out->resize(used.size());
  for (size_t j = 0; j < used.size(); ++j) {
    const size_t i = size_t(used[j]);
    const Vec3d p = world.point({xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]});
    const Vec3 f(p);
    if (!is_finite(f)) return PositionOverflow{i, p};
    (*out)[j] = f;
  }
  return std::nullopt;
}

bool all_vertices_on_boundary(const std::vector<TriangleIndices>& tris, const std::vector<Vec3d>& face) {
  std::vector<uint64_t> edges;
  edges.reserve(3 * tris.size());
  for (size_t t = 0; t < tris.size(); ++t) {
    if (norm2(face[t]) == 0) continue;
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = uint32_t(tris[t][size_t(k)]), b = uint32_t(tris[t][size_t((k + 1) % 3)]);
      edges.push_back((uint64_t(std::min(a, b)) << 32) | std::max(a, b));
    }
  }
  if (edges.empty()) return false;
  std::sort(edges.begin(), edges.end());
  std::vector<uint32_t> used, on_boundary;
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    const uint32_t a = uint32_t(edges[i] >> 32), b = uint32_t(edges[i]);
    used.push_back(a);
    used.push_back(b);
    if (j - i == 1) {
      on_boundary.push_back(a);
      on_boundary.push_back(b);
    }
    i = j;
  }
  for (auto* v : {&used, &on_boundary}) {
    std::sort(v->begin(), v->end());
    v->erase(std::unique(v->begin(), v->end()), v->end());
  }
  return used.size() == on_boundary.size();
}

size_t add_mesh_triangles(const std::vector<Vec3>& wp, const MeshTriangles& mesh, std::vector<Triangle>& out) {
  const std::vector<TriangleIndices>& tris = mesh.corners;
  const NormalSums sums = sum_normals(wp, tris);
  // The course's half-edge code gives every vertex on a mesh boundary the
  // reversed normal. For meshes made only of boundary vertices (single
  // quads and polygons: the Cornell box walls, the light quad, plane.dae)
  // that reverses the whole surface, and the course's scene files are
  // authored for it: their walls face into the box only this way. Larger
  // open meshes keep their winding (reversing just their boundary ring,
  // as the course does, flips normals across a triangle).
  const double orient = all_vertices_on_boundary(tris, sums.face) ? -1.0 : 1.0;

  // Within the scene's limit (the primitive readers checked it), and never
  // reserving past it.
  const size_t needed = out.size() + tris.size() - sums.degenerate;
  if (needed > out.capacity()) out.reserve(std::min(std::max(needed, 2 * out.capacity()), kMaxScenePrimitives));
  for (size_t t = 0; t < tris.size(); ++t) {
    if (norm2(sums.face[t]) == 0) continue;
    const Vec3d fn = normalize(sums.face[t]) * orient;
    Vec3 n[3];
    for (int k = 0; k < 3; ++k) {
      const Vec3d s = sums.vertex[size_t(tris[t][size_t(k)])];
      // Opposite faces sharing a vertex can cancel; fall back to the face.
      const double len = norm(s);
      n[k] = Vec3(len > 0 && std::isfinite(len) ? s * (orient / len) : fn);
    }
    Triangle tri;
    tri.p1 = wp[size_t(tris[t][0])];
    tri.p2 = wp[size_t(tris[t][1])];
    tri.p3 = wp[size_t(tris[t][2])];
    tri.n1 = n[0];
    tri.n2 = n[1];
    tri.n3 = n[2];
    tri.material = mesh.materials[t];
    out.push_back(tri);
  }
  return sums.degenerate;
}

}  // namespace pt::collada
