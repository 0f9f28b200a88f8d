// make_scenes: writes the project's canonical scenes (scenes/*.dae) in the
// course's COLLADA dialect.
//
//   make_scenes OUTDIR            write every scene into OUTDIR
//   make_scenes --check OUTDIR    exit 1 if any scene in OUTDIR is missing or
//                                 differs from what the generator writes
//
// The scenes are authored here from published facts about the course's
// Cornell box (dimensions, colours, light and sphere placement); see
// scenes/README.md for what each one is for. Output is deterministic: the
// same generator always writes the same bytes.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "collada_writer.h"
#include "scene_model.h"

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
struct Bounds {
  V3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  void add(V3 p) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  V3 center() const { return 0.5 * (lo + hi); }
  V3 extent() const { return hi - lo; }
};

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
//   an emissive quad (radiance 10) 0.8 wide (x) and 0.6 deep (z) just below
//   the ceiling at y = 1.49.
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
  s.meshes.push_back(quad("light", "light", {-0.4, y, -0.3}, {0.4, y, -0.3}, {0.4, y, 0.3}, {-0.4, y, 0.3}, {0, -1, 0}));
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

// The course's two spheres, radius 0.3, resting on the floor: one right and
// to the front, one left and to the back.
const V3 kSphereFrontRight{0.4, 0.3, 0.3};
const V3 kSphereBackLeft{-0.4, 0.3, -0.3};
const double kSphereRadius = 0.3;

// ---------------------------------------------------------------------------
// The scenes

Scene cb_empty() {
  Scene s;
  s.file = "CBempty.dae";
  s.purpose = "Cornell box lit by one point light (intensity 5, course attenuation), "
              "emissive ceiling quad, no objects";
  add_cornell_box(s);
  Light p;
  p.name = "PointLight";
  p.kind = LightKind::Point;
  p.color = {5, 5, 5};
  p.constant_attenuation = 1;
  p.linear_attenuation = 0;
  p.quadratic_attenuation = 0.0016;
  // At the centre of the ceiling light's plane, as in the course's file.
  p.node = zup_frame({0, kLightHeight, 0});
  s.lights.push_back(p);
  s.camera = course_camera(s, {0, 0, 1});
  return s;
}

Scene cb_spheres_lambertian() {
  Scene s;
  s.file = "CBspheres_lambertian.dae";
  s.purpose = "Cornell box with the CGL area light and two diffuse spheres (albedo 0.8)";
  add_cornell_box(s);
  s.materials.push_back(diffuse("lambertian", {0.8, 0.8, 0.8}));
  s.lights.push_back(cornell_area_light());
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
  s.lights.push_back(cornell_area_light());
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

std::vector<Scene> all_scenes() {
  return {cb_empty(), cb_spheres_lambertian(), cb_spheres(), plane_arealight(), sphere_ambient()};
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
}

std::string light_summary(const Scene& s) {
  std::string r;
  for (const Light& l : s.lights) {
    if (!r.empty()) r += ", ";
    r += l.kind == LightKind::Point ? "point" : l.kind == LightKind::Area ? "area" : "ambient";
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
  o << "usage: make_scenes [--check] OUTDIR\n"
       "  Writes the project's canonical scenes (COLLADA, course dialect) into OUTDIR.\n"
       "  --check  write nothing; exit 1 if a scene in OUTDIR is missing or out of date.\n";
}

}  // namespace

int main(int argc, char** argv) {
  bool check = false;
  std::string outdir;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help") {
      usage(std::cout);
      return 0;
    } else if (a == "--check") {
      check = true;
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

  try {
    const std::vector<Scene> scenes = all_scenes();
    if (!check) fs::create_directories(outdir);
    int stale = 0;
    for (const Scene& s : scenes) {
      validate(s);
      const std::string text = write_collada(s);
      const fs::path target = fs::path(outdir) / s.file;
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
    if (stale) {
      std::cout << stale << " scene(s) need regenerating: make_scenes " << outdir << "\n";
      return 1;
    }
  } catch (const std::exception& e) {
    std::cerr << "make_scenes: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
