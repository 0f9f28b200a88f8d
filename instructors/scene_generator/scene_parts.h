// The building blocks of the scenes: checked quads, diffuse materials, the
// course's camera placement, its Cornell box with its area light, point
// lights and ceiling lights.
#pragma once
#include <cmath>
#include <stdexcept>
#include <string>

#include "instructors/scene_generator/mesh_tools.h"
#include "instructors/scene_generator/scene_model.h"

namespace scenegen {

// ---------------------------------------------------------------------------
// Building blocks

// A planar quad a-b-c-d as the two triangles (a, b, c) and (a, c, d).
// `winding_normal` states which way the right-hand normal (b - a) x (c - a)
// of both triangles must point; the generator refuses to write anything else,
// so a typo in a corner list cannot silently flip a surface.
inline Mesh quad(const std::string& name, const std::string& material, V3 a, V3 b, V3 c, V3 d,
                 V3 winding_normal) {
  const V3 n1 = cross(b - a, c - a), n2 = cross(c - a, d - a);
  const V3 want = normalize(winding_normal);
  if (length(n1) == 0 || length(n2) == 0 || dot(normalize(n1), want) < 0.999999 ||
      dot(normalize(n2), want) < 0.999999 || std::fabs(dot(d - a, want)) > 1e-12)
    throw std::logic_error("quad '" + name + "': corners are not a planar quad wound as stated");
  return Mesh{name, material, {a, b, c, d}, {{0, 1, 2}, {0, 2, 3}}};
}

inline Material diffuse(const std::string& name, Rgb albedo) {
  Material m;
  m.name = name;
  m.kind = MaterialKind::Diffuse;
  m.diffuse = albedo;
  return m;
}

// Metals (CGL microfacet materials) of Beckmann roughness alpha. Gold: the
// index of refraction and extinction coefficient at 610, 550 and 470 nm
// (refractiveindex.info, Yakubovsky et al. 2017, a 117 nm film). Copper:
// the values of the course's bunny_microfacet_cu_unlit.dae.
inline Material metal(const std::string& name, double alpha, Rgb eta, Rgb k, Rgb look) {
  Material m = diffuse(name, look);
  m.kind = MaterialKind::Microfacet;
  m.alpha = alpha;
  m.eta = eta;
  m.k = k;
  return m;
}
// CGL glass: clear (reflectance and transmittance 1), smooth, of index `ior`.
inline Material glass(const std::string& name, double ior) {
  Material m = diffuse(name, {0.64, 0.64, 0.64});
  m.kind = MaterialKind::Glass;
  m.reflectance = {1, 1, 1};
  m.transmittance = {1, 1, 1};
  m.roughness = 0;
  m.ior = ior;
  return m;
}
inline Material gold(const std::string& name, double alpha) {
  return metal(name, alpha, {0.1884, 0.3382, 1.347}, {3.278, 2.549, 1.832}, {0.8, 0.6, 0.2});
}
inline Material copper(const std::string& name, double alpha) {
  return metal(name, alpha, {0.33228, 1.0162, 1.2474}, {3.1646, 2.5785, 2.4603}, {0.8, 0.5, 0.4});
}

// The axis-aligned bounds of all triangles and spheres (lights excluded),
// exactly as the course's camera placement sees them.
using Bounds = Box3;

inline Bounds scene_bounds(const Scene& s) {
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
inline Xform course_camera(const Scene& s, V3 dir_to_camera) {
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

inline void add_cornell_box(Scene& s) {
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
inline Light cornell_area_light() {
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
inline void add_cornell_area_light(Scene& s) {
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
inline Light point_light(const std::string& name, V3 at, Rgb intensity, double quadratic) {
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

// The course's uniform sky: an ambient light of radiance 1 (its node at the
// origin; an ambient light has no position).
inline Light ambient_light() {
  Light l;
  l.name = "AmbientLight";
  l.kind = LightKind::Ambient;
  l.color = {1, 1, 1};
  l.node = zup_frame({0, 0, 0});
  return l;
}

inline Mesh scene_mesh(const std::string& name, const std::string& material, const IndexedMesh& m, bool closed) {
  Mesh r;
  r.name = name;
  r.material = material;
  r.vertices = m.v;
  r.triangles = m.t;
  r.closed = closed;
  return r;
}

// A `2 hw` x `2 hh` quad centred at `c`, facing `facing` once loaded: the
// loader reverses the normals of a lone quad, so it is wound with its
// right-hand normal opposite `facing` (like the box's walls).
inline Mesh facing_quad(const std::string& name, const std::string& material, V3 c, V3 facing, double hw, double hh) {
  const V3 n = normalize(facing);
  const V3 u = normalize(cross(V3{0, 1, 0}, n)), v = cross(n, u);
  return quad(name, material, c - hw * u - hh * v, c - hw * u + hh * v, c + hw * u + hh * v, c + hw * u - hh * v,
              -1.0 * n);
}

// An emissive quad with a backing plate (as over the box's own light) and
// the CGL area light covering it: `sx` along x by `sz` along z, centred at
// (x, kLightHeight, z), radiance `radiance`.
inline void add_ceiling_light(Scene& s, const std::string& name, double x, double z, double sx, double sz,
                              Rgb radiance) {
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

}  // namespace scenegen
