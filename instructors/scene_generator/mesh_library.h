// The meshes taken from the pinned third-party sources (sources.txt), read,
// cleaned and decimated once for every scene that uses them.
#pragma once
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "instructors/scene_generator/decimate.h"
#include "instructors/scene_generator/mesh_tools.h"
#include "instructors/scene_generator/sources.h"
#include "instructors/scene_generator/teapot.h"

namespace scenegen {

// ---------------------------------------------------------------------------
// Meshes from the pinned third-party sources (sources.txt)

// The course's CBbunny has 28,576 triangles; ours has the same count, so
// timings compare directly.
const size_t kBunnyTriangles = 28576;
const size_t kDragonTriangles = 100000;
const size_t kLargeDragonTriangles = 200000;
// The microfacet dragons' (four scenes of one mesh, each file a copy).
const size_t kSmallDragonTriangles = 50000;
// Each of the teapot's 32 patches becomes a 16 x 16 grid of quads.
const int kTeapotSegments = 16;

// Reads the source meshes once, cleans them and keeps the results, so that
// scenes sharing a mesh (and the two dragon resolutions, made in one
// decimation pass) do the work once.
class MeshLibrary {
 public:
  explicit MeshLibrary(const SourceSet& src) : src_(src) {}

  // The Stanford bunny: CGAL's closed bunny00.off (75,408 triangles),
  // decimated.
  const IndexedMesh& bunny() {
    if (!bunny_) bunny_ = std::make_unique<IndexedMesh>(decimate(closed_source("bunny00.off"), {kBunnyTriangles})[0]);
    return *bunny_;
  }
  // The Stanford dragon: the full-resolution reconstruction (871,414
  // triangles), welded and decimated to 200,000, then 100,000, then 50,000
  // triangles.
  const IndexedMesh& dragon(size_t triangles) {
    if (dragons_.empty()) {
      std::vector<IndexedMesh> d = decimate(closed_source("dragon_vrip.ply"),
                                            {kLargeDragonTriangles, kDragonTriangles, kSmallDragonTriangles});
      dragons_[kLargeDragonTriangles] = std::move(d[0]);
      dragons_[kDragonTriangles] = std::move(d[1]);
      dragons_[kSmallDragonTriangles] = std::move(d[2]);
    }
    return dragons_.at(triangles);
  }
  // The Stanford armadillo as CGAL distributes it (52,000 triangles, closed).
  const IndexedMesh& armadillo() {
    if (!armadillo_) armadillo_ = std::make_unique<IndexedMesh>(closed_source("armadillo.off"));
    return *armadillo_;
  }
  // CGAL's cow (5,804 triangles, closed).
  const IndexedMesh& cow() {
    if (!cow_) cow_ = std::make_unique<IndexedMesh>(closed_source("cow.off"));
    return *cow_;
  }
  // The Utah teapot from its Bezier patches. Not closed: the lid and body
  // do not meet, and the spout and handle end open inside the body.
  const IndexedMesh& teapot() {
    if (!teapot_) {
      const std::string name = "TeapotGeometry.js";
      IndexedMesh m = tessellate_patches(read_teapot_patches(src_.read(name), src_.path(name)), kTeapotSegments);
      // The patches' (u, v) order makes dP/du x dP/dv point into the pot.
      reverse_winding(m);
      // The data is Z up with the spout along +X: turn it to Y up
      // (x, y, z) -> (x, z, -y), a rotation.
      for (V3& p : m.v) p = V3{p.x, p.z, -p.y};
      teapot_ = std::make_unique<IndexedMesh>(std::move(m));
    }
    return *teapot_;
  }

 private:
  // Reads an OFF or PLY source, merges its duplicate vertices (keeping
  // apart the sheets of a surface that merely touch at a point), checks
  // that it is closed and winds it outward (positive enclosed volume).
  IndexedMesh closed_source(const std::string& name) {
    const std::string text = src_.read(name);
    const std::string what = src_.path(name);
    IndexedMesh m = name.size() > 4 && name.compare(name.size() - 4, 4, ".ply") == 0 ? read_ply_ascii(text, what)
                                                                                      : read_off(text, what);
    m = weld_exact(m);
    const Topology t = topology(m);
    if (!t.closed())
      throw std::runtime_error(what + ": expected a closed mesh after welding (" + std::to_string(t.boundary_edges) +
                               " boundary, " + std::to_string(t.nonmanifold_edges) + " non-manifold, " +
                               std::to_string(t.misoriented_edges) + " misoriented edges)");
    m = split_pinched_vertices(m);
    if (signed_volume(m) < 0) reverse_winding(m);
    return m;
  }

  const SourceSet& src_;
  std::unique_ptr<IndexedMesh> bunny_, armadillo_, cow_, teapot_;
  std::map<size_t, IndexedMesh> dragons_;
};

}  // namespace scenegen
