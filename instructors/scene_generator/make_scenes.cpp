// make_scenes: writes the project's canonical scenes (scenes/*.dae) in the
// course's COLLADA dialect.
//
//   make_scenes [OPTIONS] OUTDIR         write every scene into OUTDIR
//   make_scenes --check [OPTIONS] OUTDIR exit 1 if a scene in OUTDIR is
//                                        missing or differs from what the
//                                        generator writes
// Options:
//   --sources DIR       the folder fetch_sources.sh filled (default:
//                       $PT_SCENE_SOURCES, else the repository's
//                       build/scene-sources)
//   --no-sources        build only the scenes that need no third-party data
//   --require-sources   fail (exit 1) if any scene had to be skipped
//
// The Cornell boxes and the analytic scenes are authored here from
// published facts about the course's scenes. The mesh scenes are built from
// pinned third-party files (sources.txt): a scene whose sources are not in
// the cache is skipped, and said so; with --check its committed file must
// still exist. See scenes/README.md for what each scene is for. Output is
// deterministic: the same generator and sources always write the same bytes.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <iterator>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "instructors/scene_generator/collada_writer.h"
#include "instructors/scene_generator/decimate.h"
#include "instructors/scene_generator/mesh_tools.h"
#include "instructors/scene_generator/scene_model.h"
#include "instructors/scene_generator/sources.h"
#include "instructors/scene_generator/teapot.h"

#ifndef PT_SCENE_MANIFEST
#error "PT_SCENE_MANIFEST (the path of sources.txt) must be defined by the build"
#endif
#ifndef PT_SCENE_SOURCES_DEFAULT
#error "PT_SCENE_SOURCES_DEFAULT (the default source cache) must be defined by the build"
#endif

namespace fs = std::filesystem;
using namespace scenegen;

namespace {

// ---------------------------------------------------------------------------
// Building blocks

// A planar quad a-b-c-d as the two triangles (a, b, c) and (a, c, d).
// `winding_normal` states which way the right-hand normal (b - a) x (c - a)
// of both triangles must point; the generator refuses to write anything else,
// so a typo in a corner list cannot silently flip a surface.
Mesh quad(const std::string& name, const std::string& material, V3 a, V3 b, V3 c, V3 d,
          V3 winding_normal) {
  const V3 n1 = cross(b - a, c - a), n2 = cross(c - a, d - a);
  const V3 want = normalize(winding_normal);
  if (length(n1) == 0 || length(n2) == 0 || dot(normalize(n1), want) < 0.999999 ||
      dot(normalize(n2), want) < 0.999999 || std::fabs(dot(d - a, want)) > 1e-12)
    throw std::logic_error("quad '" + name + "': corners are not a planar quad wound as stated");
  return Mesh{name, material, {a, b, c, d}, {{0, 1, 2}, {0, 2, 3}}};
}

Material diffuse(const std::string& name, Rgb albedo) {
  Material m;
  m.name = name;
  m.kind = MaterialKind::Diffuse;
  m.diffuse = albedo;
  return m;
}

// The axis-aligned bounds of all triangles and spheres (lights excluded),
// exactly as the course's camera placement sees them.
using Bounds = Box3;

Bounds scene_bounds(const Scene& s) {
  Bounds b;
  for (const Mesh& m : s.meshes)
    for (const auto& t : m.triangles)
      for (int i : t) b.add(m.vertices[i]);
  for (const Sphere& sp : s.spheres) {
    b.add(sp.center - V3{sp.radius, sp.radius, sp.radius});
    b.add(sp.center + V3{sp.radius, sp.radius, sp.radius});
  }
  return b;
}

// The camera node for the course's placement rule. The course ignores the
// node's position: it takes c_dir = normalize(T (0,0,-1,1)) as a direction
// from the world origin and looks from target + 1.5 |extent| c_dir at the
// bounds' centre. We put the node on that ray through the origin, at the
// same distance, facing the origin, so T (0,0,-1,1) lies exactly on it and
// the node's own pose is a sensible view for readers that do use it (it is
// the course's pose whenever the bounds are centred on the origin).
Xform course_camera(const Scene& s, V3 dir_to_camera) {
  const double dist = 1.5 * length(scene_bounds(s).extent());
  const V3 d = normalize(dir_to_camera);
  return camera_frame(dist * d, d);
}

// ---------------------------------------------------------------------------
// The course's Cornell box (world space, Y up):
//   x in [-1, 1], y in [0, 1.5], z in [-1, 1], open at z = +1;
//   floor, ceiling and back wall 0.6 grey, left wall (x = -1) red
//   0.6 0.2 0.2, right wall (x = +1) blue 0.2 0.2 0.6;
//   an emissive quad (radiance 10) just below the ceiling at y = 1.49,
//   covering the area light's rectangle (0.6 along x, 0.8 along z).
// Winding follows the course's files: each wall's right-hand normal points
// out of the box and the light quad's points down. (The course recomputes
// normals from the winding; keeping its winding keeps its shading.)

const double kBoxHeight = 1.5;
const double kLightHeight = 1.49;

void add_cornell_box(Scene& s) {
  s.materials.push_back(diffuse("floor", {0.6, 0.6, 0.6}));
  s.materials.push_back(diffuse("ceiling", {0.6, 0.6, 0.6}));
  s.materials.push_back(diffuse("backWall", {0.6, 0.6, 0.6}));
  s.materials.push_back(diffuse("leftWall", {0.6, 0.2, 0.2}));
  s.materials.push_back(diffuse("rightWall", {0.2, 0.2, 0.6}));
  Material light = diffuse("light", {0.8, 0.8, 0.8});
  light.kind = MaterialKind::Emission;
  light.emission = {10, 10, 10};
  s.materials.push_back(light);

  const double h = kBoxHeight, y = kLightHeight;
  s.meshes.push_back(quad("floor", "floor", {-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}, {0, -1, 0}));
  s.meshes.push_back(quad("ceiling", "ceiling", {-1, h, -1}, {-1, h, 1}, {1, h, 1}, {1, h, -1}, {0, 1, 0}));
  s.meshes.push_back(quad("backWall", "backWall", {-1, 0, -1}, {-1, h, -1}, {1, h, -1}, {1, 0, -1}, {0, 0, -1}));
  s.meshes.push_back(quad("leftWall", "leftWall", {-1, 0, -1}, {-1, 0, 1}, {-1, h, 1}, {-1, h, -1}, {-1, 0, 0}));
  s.meshes.push_back(quad("rightWall", "rightWall", {1, 0, -1}, {1, h, -1}, {1, h, 1}, {1, 0, 1}, {1, 0, 0}));
  // The quad covers exactly the area light's rectangle (0.6 along x, 0.8
  // along z), so that hemisphere sampling (-H), which sees the quad, and
  // light sampling, which samples the light, estimate the same light. (The
  // course's quad is the light turned by 90 degrees.)
  s.meshes.push_back(quad("light", "light", {-0.3, y, -0.4}, {0.3, y, -0.4}, {0.3, y, 0.4}, {-0.3, y, 0.4}, {0, -1, 0}));
}

// The course's CGL area light: the node scales a unit square 0.6 (file x,
// world x) by 0.8 (file y, world z) at world height 1.49, emitting along the
// node's -Z, i.e. straight down. Radiance 10; the point-light fallback has
// the same colour, as in the course's files.
Light cornell_area_light() {
  Light l;
  l.name = "AreaLight";
  l.kind = LightKind::Area;
  l.color = {10, 10, 10};
  l.node = zup_frame({0, kLightHeight, 0}, 0.6, 0.8, 1);
  return l;
}

// The area light, and a backing plate over the emissive quad. Emission is
// seen from both sides (as in the course), while the area light shines only
// down; without the plate the ceiling, 1 cm above the quad, would be lit by
// the quad's back under hemisphere sampling (-H) but not under light
// sampling. The plate (ceiling material, 0.1 mm above the quad, 1 cm wider
// on every side, wound like the floor so that it faces up) hides the back,
// and the two estimators agree. Scenes with only a point light (CBempty)
// keep the course's box.
void add_cornell_area_light(Scene& s) {
  s.lights.push_back(cornell_area_light());
  const double y = kLightHeight + 1e-4;
  s.meshes.push_back(
      quad("lightBacking", "ceiling", {-0.31, y, -0.41}, {0.31, y, -0.41}, {0.31, y, 0.41}, {-0.31, y, 0.41}, {0, -1, 0}));
}

// The course's two spheres, radius 0.3, resting on the floor: one right and
// to the front, one left and to the back.
const V3 kSphereFrontRight{0.4, 0.3, 0.3};
const V3 kSphereBackLeft{-0.4, 0.3, -0.3};
const double kSphereRadius = 0.3;

// The quadratic attenuation of the course's point lights (almost none).
const double kCourseFalloff = 0.0016;

// A point light of `intensity` at `at`, attenuated by
// 1 / (1 + quadratic d^2).
Light point_light(const std::string& name, V3 at, Rgb intensity, double quadratic) {
  Light p;
  p.name = name;
  p.kind = LightKind::Point;
  p.color = intensity;
  p.constant_attenuation = 1;
  p.linear_attenuation = 0;
  p.quadratic_attenuation = quadratic;
  p.node = zup_frame(at);
  return p;
}

// ---------------------------------------------------------------------------
// The scenes

Scene cb_empty() {
  Scene s;
  s.file = "CBempty.dae";
  s.purpose = "Cornell box lit by one point light (intensity 5, course attenuation), "
              "emissive ceiling quad, no objects";
  add_cornell_box(s);
  // At the centre of the ceiling light's plane, as in the course's file.
  s.lights.push_back(point_light("PointLight", {0, kLightHeight, 0}, {5, 5, 5}, kCourseFalloff));
  s.camera = course_camera(s, {0, 0, 1});
  return s;
}

Scene cb_spheres_lambertian() {
  Scene s;
  s.file = "CBspheres_lambertian.dae";
  s.purpose = "Cornell box with the CGL area light and two diffuse spheres (albedo 0.8)";
  add_cornell_box(s);
  s.materials.push_back(diffuse("lambertian", {0.8, 0.8, 0.8}));
  add_cornell_area_light(s);
  s.spheres.push_back({"SphereFrontRight", "lambertian", kSphereFrontRight, kSphereRadius});
  s.spheres.push_back({"SphereBackLeft", "lambertian", kSphereBackLeft, kSphereRadius});
  s.camera = course_camera(s, {0, 0, 1});
  return s;
}

Scene cb_spheres() {
  Scene s;
  s.file = "CBspheres.dae";
  s.purpose = "Cornell box with the CGL area light, a glass sphere (front right) "
              "and a mirror sphere (back left)";
  add_cornell_box(s);
  Material glass = diffuse("glass", {0.64, 0.64, 0.64});
  glass.kind = MaterialKind::Glass;
  glass.reflectance = {1, 1, 1};
  glass.transmittance = {1, 1, 1};
  glass.roughness = 0;
  glass.ior = 1.45;  // the course's value for this scene
  Material mirror = diffuse("mirror", {0.64, 0.64, 0.64});
  mirror.kind = MaterialKind::Mirror;
  mirror.reflectance = {1, 1, 1};
  s.materials.push_back(glass);
  s.materials.push_back(mirror);
  add_cornell_area_light(s);
  s.spheres.push_back({"SphereFrontRight", "glass", kSphereFrontRight, kSphereRadius});
  s.spheres.push_back({"SphereBackLeft", "mirror", kSphereBackLeft, kSphereRadius});
  s.camera = course_camera(s, {0, 0, 1});
  return s;
}

// An analytic test: a 2 x 2 diffuse square (albedo 0.5) in the plane y = 0
// under a 0.5 x 0.5 area light of radiance 1 centred 1 unit above it, facing
// down. Only the plane is geometry; the light is not visible to camera rays.
Scene plane_arealight() {
  Scene s;
  s.file = "plane_arealight.dae";
  s.purpose = "2 x 2 diffuse plane (albedo 0.5) at y = 0 under a 0.5 x 0.5 area light "
              "of radiance 1 at y = 1 facing down; for exact tests";
  s.materials.push_back(diffuse("plane", {0.5, 0.5, 0.5}));
  // Wound like the course's floor (right-hand normal down).
  s.meshes.push_back(quad("plane", "plane", {-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}, {0, -1, 0}));
  Light l;
  l.name = "AreaLight";
  l.kind = LightKind::Area;
  l.color = {1, 1, 1};
  l.node = zup_frame({0, 1, 0}, 0.5, 0.5, 1);
  s.lights.push_back(l);
  // Looking down at the plane's centre from 45 degrees above the front edge.
  s.camera = course_camera(s, {0, 1, 1});
  return s;
}

// An analytic test: a diffuse sphere (albedo 0.5, radius 0.5) at the origin
// under a uniform ambient light of radiance 1 over the +Y hemisphere.
Scene sphere_ambient() {
  Scene s;
  s.file = "sphere_ambient.dae";
  s.purpose = "diffuse sphere (albedo 0.5, radius 0.5) at the origin under an ambient "
              "light of radiance 1; for exact tests";
  s.materials.push_back(diffuse("sphere", {0.5, 0.5, 0.5}));
  s.spheres.push_back({"Sphere", "sphere", {0, 0, 0}, 0.5});
  Light l;
  l.name = "AmbientLight";
  l.kind = LightKind::Ambient;
  l.color = {1, 1, 1};
  l.node = zup_frame({0, 0, 0});
  s.lights.push_back(l);
  s.camera = course_camera(s, {0, 0, 1});
  return s;
}

Mesh scene_mesh(const std::string& name, const std::string& material, const IndexedMesh& m, bool closed) {
  Mesh r;
  r.name = name;
  r.material = material;
  r.vertices = m.v;
  r.triangles = m.t;
  r.closed = closed;
  return r;
}

// Grading scenes: each shows one thing that the standard scenes hide.

// A `2 hw` x `2 hh` quad centred at `c`, facing `facing` once loaded: the
// loader reverses the normals of a lone quad, so it is wound with its
// right-hand normal opposite `facing` (like the box's walls).
Mesh facing_quad(const std::string& name, const std::string& material, V3 c, V3 facing, double hw, double hh) {
  const V3 n = normalize(facing);
  const V3 u = normalize(cross(V3{0, 1, 0}, n)), v = cross(n, u);
  return quad(name, material, c - hw * u - hh * v, c - hw * u + hh * v, c + hw * u + hh * v, c + hw * u - hh * v,
              -1.0 * n);
}

// Part 1: primitives listed nearest first, overlapping in view, so that an
// intersection routine which lets a later (farther) primitive overwrite an
// earlier (nearer) hit shows. Brute force tests the triangles in file
// order, then the spheres: quad A (front) is listed before quad B, which it
// partly hides, and both before the back wall; sphere S1 (front) is listed
// before sphere S2, which it partly hides; S2 also lies partly behind quad
// B, a triangle tested before it.
Scene depth_order() {
  Scene s;
  s.file = "depth_order.dae";
  s.purpose = "overlapping quads and spheres listed nearest first: the nearest hit must win over the last one "
              "tested (part 1)";
  s.materials.push_back(diffuse("front", {0.7, 0.7, 0.7}));
  s.materials.push_back(diffuse("middle", {0.5, 0.5, 0.5}));
  s.materials.push_back(diffuse("back", {0.3, 0.3, 0.3}));
  // Each quad faces the camera turned its own way, so that normal shading
  // tells them apart.
  s.meshes.push_back(facing_quad("quadA", "front", {-0.4, 0.6, 0.6}, {0.5, 0.3, 1}, 0.3, 0.3));
  s.meshes.push_back(facing_quad("quadB", "middle", {0.15, 0.45, 0.2}, {-0.4, -0.3, 1}, 0.4, 0.3));
  s.meshes.push_back(facing_quad("backWall", "back", {0, 0.75, -0.6}, {0, 0, 1}, 1, 0.75));
  s.spheres.push_back({"SphereFront", "front", {0.35, 0.9, 0.5}, 0.25});
  s.spheres.push_back({"SphereBack", "middle", {0.5, 0.75, -0.2}, 0.3});
  s.lights.push_back(point_light("PointLight", {0, 1.4, 1.0}, {3, 3, 3}, 0));
  s.camera = course_camera(s, {0, 0, 1});
  return s;
}

// An emissive quad with a backing plate (as over the box's own light) and
// the CGL area light covering it: `sx` along x by `sz` along z, centred at
// (x, kLightHeight, z), radiance `radiance`.
void add_ceiling_light(Scene& s, const std::string& name, double x, double z, double sx, double sz, Rgb radiance) {
  Material m = diffuse(name, {0.8, 0.8, 0.8});
  m.kind = MaterialKind::Emission;
  m.emission = radiance;
  s.materials.push_back(m);
  const double y = kLightHeight, hx = sx / 2, hz = sz / 2;
  s.meshes.push_back(quad(name, name, {x - hx, y, z - hz}, {x + hx, y, z - hz}, {x + hx, y, z + hz}, {x - hx, y, z + hz},
                          {0, -1, 0}));
  const double b = y + 1e-4;
  s.meshes.push_back(quad(name + "Backing", "ceiling", {x - hx - 0.01, b, z - hz - 0.01}, {x + hx + 0.01, b, z - hz - 0.01},
                          {x + hx + 0.01, b, z + hz + 0.01}, {x - hx - 0.01, b, z + hz + 0.01}, {0, -1, 0}));
  Light l;
  l.name = name + "Area";
  l.kind = LightKind::Area;
  l.color = radiance;
  l.node = zup_frame({x, y, z}, sx, sz, 1);
  s.lights.push_back(l);
}

// Part 3: two area lights and two point lights, each pair of different
// sizes, colours and places, so that sampling only one light of a kind,
// averaging the lights instead of summing them, or sampling a delta light
// -l times all show.
Scene cb_lights() {
  Scene s;
  s.file = "CBlights.dae";
  s.purpose = "Cornell box with two diffuse spheres, two CGL area lights and two point lights of different "
              "colours (part 3: every light counts, once)";
  add_cornell_box(s);
  // Not the box's central light: two smaller ones of their own.
  s.meshes.pop_back();
  s.materials.erase(std::remove_if(s.materials.begin(), s.materials.end(),
                                   [](const Material& m) { return m.name == "light"; }),
                    s.materials.end());
  s.materials.push_back(diffuse("lambertian", {0.8, 0.8, 0.8}));
  add_ceiling_light(s, "lightWarm", -0.45, -0.2, 0.4, 0.3, {8, 6, 4});
  add_ceiling_light(s, "lightCool", 0.5, 0.3, 0.3, 0.5, {3, 5, 9});
  s.lights.push_back(point_light("PointLightLeft", {-0.55, 1.1, 0.55}, {1.2, 1.0, 0.6}, kCourseFalloff));
  s.lights.push_back(point_light("PointLightRight", {0.6, 0.8, -0.5}, {0.5, 0.8, 1.4}, kCourseFalloff));
  s.spheres.push_back({"SphereFrontRight", "lambertian", kSphereFrontRight, kSphereRadius});
  s.spheres.push_back({"SphereBackLeft", "lambertian", kSphereBackLeft, kSphereRadius});
  s.camera = course_camera(s, {0, 0, 1});
  return s;
}

// ---------------------------------------------------------------------------
// Meshes from the pinned third-party sources (sources.txt)

// The course's CBbunny has 28,576 triangles; ours has the same count, so
// timings compare directly.
const size_t kBunnyTriangles = 28576;
const size_t kDragonTriangles = 100000;
const size_t kLargeDragonTriangles = 200000;
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
  // triangles), welded and decimated to 200,000 and then 100,000 triangles.
  const IndexedMesh& dragon(size_t triangles) {
    if (dragons_.empty()) {
      std::vector<IndexedMesh> d =
          decimate(closed_source("dragon_vrip.ply"), {kLargeDragonTriangles, kDragonTriangles});
      dragons_[kLargeDragonTriangles] = std::move(d[0]);
      dragons_[kDragonTriangles] = std::move(d[1]);
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


// The course's CBbunny, stated in our (unmirrored) box: the bunny stands on
// the floor in the middle of the box, 0.772 tall (its bounding box is about
// 0.78 wide, 0.77 tall and 0.60 deep), its lowest point 2 mm above the
// floor. Our camera looks from +z where the course's file looks from -z at a
// mirrored box; keeping the bunny in its source orientation here gives the
// same view of it as the course's image (head on the left).
Scene cb_bunny(MeshLibrary& lib) {
  Scene s;
  s.file = "CBbunny.dae";
  s.purpose = "Cornell box with the CGL area light and the Stanford bunny (28,576 triangles, diffuse 0.5)";
  add_cornell_box(s);
  s.materials.push_back(diffuse("bunny", {0.5, 0.5, 0.5}));
  add_cornell_area_light(s);
  IndexedMesh m = lib.bunny();
  place_on_floor(m, 0, 1, 0.772, 0.002);
  s.meshes.push_back(scene_mesh("bunny", "bunny", m, true));
  s.camera = course_camera(s, {0, 0, 1});
  return s;
}

// The Stanford dragon in the box, side on (head to the left), 1.4 long
// (x), on the floor.
Scene cb_dragon(MeshLibrary& lib, size_t triangles, const std::string& file, const std::string& purpose) {
  Scene s;
  s.file = file;
  s.purpose = purpose;
  add_cornell_box(s);
  s.materials.push_back(diffuse("dragon", {0.5, 0.5, 0.5}));
  add_cornell_area_light(s);
  IndexedMesh m = lib.dragon(triangles);
  place_on_floor(m, 0, 0, 1.4, 0.002);
  s.meshes.push_back(scene_mesh("dragon", "dragon", m, true));
  s.camera = course_camera(s, {0, 0, 1});
  return s;
}

// Like the course's meshedit scenes (cow.dae): one diffuse mesh (albedo
// 0.48) in empty space, lit by a directional light of radiance 1 from
// (-0.5, 0.7071, 0.5) (up, left and in front). The mesh is centred on the
// origin with its largest side 1 long, after turning it by
// `rotate_y_degrees` about +Y to face the camera. The light's node sits 2 units out
// along that direction with its -Z axis pointing back: readers that take the
// direction from the node's rotation and readers that (like the course)
// take it from the point T (0,0,-1,1) then find the same direction.
Scene open_mesh_scene(const std::string& file, const std::string& purpose, const std::string& name,
                      IndexedMesh m, bool closed, double rotate_y_degrees, V3 dir_to_camera) {
  Scene s;
  s.file = file;
  s.purpose = purpose;
  s.materials.push_back(diffuse(name, {0.48, 0.48, 0.48}));
  for (V3& p : m.v) p = rotate_y(p, rotate_y_degrees);
  center_and_fit(m, 1.0);
  s.meshes.push_back(scene_mesh(name, name, m, closed));
  Light l;
  l.name = "DirectionalLight";
  l.kind = LightKind::Directional;
  l.color = {1, 1, 1};
  const V3 toward_light = normalize(V3{-0.5, 0.70710678118654752, 0.5});
  l.node = camera_frame(2.0 * toward_light, toward_light);
  s.lights.push_back(l);
  s.camera = course_camera(s, dir_to_camera);
  return s;
}

Scene cow(MeshLibrary& lib) {
  return open_mesh_scene("cow.dae", "the cow (5,804 triangles) under a directional light, like the course's meshedit scenes",
                         "cow", lib.cow(), true, 0, {0, 0, 1});
}

Scene teapot(MeshLibrary& lib) {
  return open_mesh_scene("teapot.dae",
                         "the Utah teapot (16,256 triangles from its 32 Bezier patches, open) under a directional light",
                         "teapot", lib.teapot(), false, 0, {0, 0.5, 1});
}

Scene armadillo(MeshLibrary& lib) {
  return open_mesh_scene("armadillo.dae", "the Stanford armadillo (52,000 triangles) under a directional light",
                         "armadillo", lib.armadillo(), true, 180, {0, 0, 1});
}

// The bunny of CBbunny, same size, on a 2 x 2 diffuse ground square under
// an ambient (uniform sky) light of radiance 1: lighting that hemisphere
// sampling (-H) and light sampling both reach, for comparing them.
Scene bunny_ambient(MeshLibrary& lib) {
  Scene s;
  s.file = "bunny_ambient.dae";
  s.purpose = "the Stanford bunny (28,576 triangles, diffuse 0.5) on a 2 x 2 ground square (diffuse 0.5) "
              "under an ambient light of radiance 1";
  s.materials.push_back(diffuse("ground", {0.5, 0.5, 0.5}));
  s.materials.push_back(diffuse("bunny", {0.5, 0.5, 0.5}));
  // Wound like the Cornell box floor (right-hand normal down), so that it
  // faces up once the loader reverses the normals of a lone quad.
  s.meshes.push_back(quad("ground", "ground", {-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}, {0, -1, 0}));
  IndexedMesh m = lib.bunny();
  place_on_floor(m, 0, 1, 0.772, 0.002);
  s.meshes.push_back(scene_mesh("bunny", "bunny", m, true));
  Light l;
  l.name = "AmbientLight";
  l.kind = LightKind::Ambient;
  l.color = {1, 1, 1};
  l.node = zup_frame({0, 0, 0});
  s.lights.push_back(l);
  s.camera = course_camera(s, {0, 0.5, 1});
  return s;
}

// ---------------------------------------------------------------------------
// The scene list

struct Recipe {
  std::string file;
  std::vector<std::string> sources;  // files from sources.txt; none for authored scenes
  std::function<Scene(MeshLibrary&)> build;
};

std::vector<Recipe> all_recipes() {
  auto authored = [](Scene (*f)()) { return [f](MeshLibrary&) { return f(); }; };
  return {
      {"CBempty.dae", {}, authored(cb_empty)},
      {"CBspheres_lambertian.dae", {}, authored(cb_spheres_lambertian)},
      {"CBspheres.dae", {}, authored(cb_spheres)},
      {"plane_arealight.dae", {}, authored(plane_arealight)},
      {"sphere_ambient.dae", {}, authored(sphere_ambient)},
      {"depth_order.dae", {}, authored(depth_order)},
      {"CBlights.dae", {}, authored(cb_lights)},
      {"CBbunny.dae", {"bunny00.off"}, cb_bunny},
      {"CBdragon.dae", {"dragon_vrip.ply"},
       [](MeshLibrary& lib) {
         return cb_dragon(lib, kDragonTriangles, "CBdragon.dae",
                          "Cornell box with the CGL area light and the Stanford dragon (100,000 triangles, diffuse 0.5)");
       }},
      {"CBdragon_large.dae", {"dragon_vrip.ply"},
       [](MeshLibrary& lib) {
         return cb_dragon(lib, kLargeDragonTriangles, "CBdragon_large.dae",
                          "Cornell box with the CGL area light and the Stanford dragon at 200,000 triangles, "
                          "a scene that needs a BVH");
       }},
      {"cow.dae", {"cow.off"}, cow},
      {"teapot.dae", {"TeapotGeometry.js"}, teapot},
      {"armadillo.dae", {"armadillo.off"}, armadillo},
      {"bunny_ambient.dae", {"bunny00.off"}, bunny_ambient},
  };
}

// ---------------------------------------------------------------------------
// Checks and the summary line

// The course's camera position, computed from what is written: the node
// matrix in file coordinates mapped back to world space.
V3 course_camera_position(const Scene& s) {
  const auto m = node_matrix(s.camera);
  const V3 front_file{m[3] - m[2], m[7] - m[6], m[11] - m[10]};  // M (0,0,-1,1)
  const V3 c_dir = normalize(zup_to_world(front_file));
  const Bounds b = scene_bounds(s);
  return b.center() + (1.5 * length(b.extent())) * c_dir;
}

// Moves every mesh vertex to exactly the position its printed coordinates
// give back, so that the checks below see what a reader of the file sees.
// (Printing the snapped numbers again gives the same text.)
void snap_to_file_precision(Scene& s) {
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
void validate_mesh(const Scene& s, const Mesh& m) {
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

void validate(const Scene& s) {
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

std::string light_summary(const Scene& s) {
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

std::string summary(const Scene& s) {
  const V3 c = course_camera_position(s);
  std::ostringstream o;
  o << s.file << ": " << s.triangle_count() << " triangles, " << s.spheres.size() << " sphere(s), "
    << s.lights.size() << " light(s) (" << light_summary(s) << "); course camera at (" << num(c.x)
    << ", " << num(c.y) << ", " << num(c.z) << ")";
  return o.str();
}

// ---------------------------------------------------------------------------
// Files

bool read_file(const fs::path& p, std::string& out) {
  std::ifstream in(p, std::ios::binary);
  if (!in) return false;
  out.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return true;
}

// Write to a temporary name in the same directory, then rename over the
// target, so a reader never sees a half-written scene.
void write_atomically(const fs::path& target, const std::string& text) {
  const fs::path tmp = target.parent_path() / (target.filename().string() + ".tmp.make_scenes");
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot create " + tmp.string());
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    out.close();
    if (!out) {
      std::error_code ec;
      fs::remove(tmp, ec);
      throw std::runtime_error("cannot write " + tmp.string());
    }
  }
  std::error_code ec;
  fs::rename(tmp, target, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw std::runtime_error("cannot rename " + tmp.string() + " to " + target.string() + ": " + ec.message());
  }
}

void usage(std::ostream& o) {
  o << "usage: make_scenes [--check] [--sources DIR | --no-sources] [--require-sources] OUTDIR\n"
       "  Writes the project's canonical scenes (COLLADA, course dialect) into OUTDIR.\n"
       "  --check            write nothing; exit 1 if a scene in OUTDIR is missing or out of date\n"
       "  --sources DIR      where fetch_sources.sh put the pinned mesh sources (default:\n"
       "                     $PT_SCENE_SOURCES, else " PT_SCENE_SOURCES_DEFAULT ")\n"
       "  --no-sources       only the scenes that need no third-party data\n"
       "  --require-sources  exit 1 if a scene is skipped because its sources are missing\n"
       "  Scenes whose sources are not fetched are skipped and listed; with --check their\n"
       "  files must still exist in OUTDIR.\n";
}

}  // namespace

int main(int argc, char** argv) {
  bool check = false, no_sources = false, require_sources = false;
  std::string outdir, sources_dir;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help") {
      usage(std::cout);
      return 0;
    } else if (a == "--check") {
      check = true;
    } else if (a == "--no-sources") {
      no_sources = true;
    } else if (a == "--require-sources") {
      require_sources = true;
    } else if (a == "--sources") {
      if (i + 1 >= argc) {
        std::cerr << "make_scenes: --sources needs a folder\n";
        return 2;
      }
      sources_dir = argv[++i];
    } else if (!a.empty() && a[0] == '-') {
      std::cerr << "make_scenes: unknown option " << a << "\n";
      usage(std::cerr);
      return 2;
    } else if (outdir.empty()) {
      outdir = a;
    } else {
      std::cerr << "make_scenes: more than one OUTDIR given\n";
      usage(std::cerr);
      return 2;
    }
  }
  if (outdir.empty()) {
    usage(std::cerr);
    return 2;
  }
  if (no_sources && (!sources_dir.empty() || require_sources)) {
    std::cerr << "make_scenes: --no-sources cannot be combined with --sources or --require-sources\n";
    return 2;
  }
  if (!no_sources && sources_dir.empty()) {
    const char* env = std::getenv("PT_SCENE_SOURCES");
    sources_dir = env && *env ? env : PT_SCENE_SOURCES_DEFAULT;
  }

  try {
    const SourceSet sources(PT_SCENE_MANIFEST, no_sources ? std::string() : sources_dir);
    MeshLibrary library(sources);
    if (!check) fs::create_directories(outdir);
    int stale = 0;
    std::vector<std::string> skipped;
    for (const Recipe& r : all_recipes()) {
      const fs::path target = fs::path(outdir) / r.file;
      std::vector<std::string> absent;
      for (const std::string& name : r.sources)
        if (!sources.available(name)) absent.push_back(name);
      if (!absent.empty()) {
        std::string need;
        for (const std::string& n : absent) need += (need.empty() ? "" : ", ") + n;
        skipped.push_back(r.file);
        if (check && !fs::exists(target)) {
          std::cout << "missing: " << target.string() << " (and its sources: " << need << ")\n";
          ++stale;
        } else {
          std::cout << "skipped: " << r.file << " (needs " << need << ")\n";
        }
        continue;
      }
      Scene s = r.build(library);
      if (s.file != r.file) throw std::logic_error("recipe " + r.file + " built " + s.file);
      snap_to_file_precision(s);
      validate(s);
      const std::string text = write_collada(s);
      if (check) {
        std::string current;
        if (!read_file(target, current)) {
          std::cout << "missing: " << target.string() << "\n";
          ++stale;
        } else if (current != text) {
          std::cout << "out of date: " << target.string() << "\n";
          ++stale;
        } else {
          std::cout << "up to date: " << summary(s) << "\n";
        }
      } else {
        write_atomically(target, text);
        std::cout << "wrote " << target.string() << "  [" << summary(s) << "]\n";
      }
    }
    if (!skipped.empty())
      std::cout << skipped.size() << " scene(s) skipped: "
                << (no_sources ? std::string("--no-sources was given")
                               : "their sources are not in " + sources_dir + "/files") +
                       "; fetch them with instructors/scene_generator/fetch_sources.sh to "
                << (check ? "check" : "build") << " those too\n";
    if (stale) {
      std::cout << stale << " scene(s) missing or out of date; rebuild with make_scenes " << outdir
                << " (the mesh scenes need their sources: instructors/scene_generator/fetch_sources.sh)\n";
      return 1;
    }
    if (require_sources && !skipped.empty()) {
      std::cout << "make_scenes: --require-sources: " << skipped.size() << " scene(s) were skipped\n";
      return 1;
    }
  } catch (const std::exception& e) {
    std::cerr << "make_scenes: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
