// The scenes authored here from published facts about the course's scenes:
// the Cornell boxes, the analytic scenes and the grading scenes. They need
// no third-party data.
#pragma once
#include <algorithm>

#include "instructors/scene_generator/scene_model.h"
#include "instructors/scene_generator/scene_parts.h"

namespace scenegen {

// ---------------------------------------------------------------------------
// The scenes

inline Scene cb_empty() {
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

inline Scene cb_spheres_lambertian() {
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

inline Scene cb_spheres() {
  Scene s;
  s.file = "CBspheres.dae";
  s.purpose = "Cornell box with the CGL area light, a glass sphere (front right) "
              "and a mirror sphere (back left)";
  add_cornell_box(s);
  const Material clear = glass("glass", 1.45);  // the course's value for this scene
  Material mirror = diffuse("mirror", {0.64, 0.64, 0.64});
  mirror.kind = MaterialKind::Mirror;
  mirror.reflectance = {1, 1, 1};
  s.materials.push_back(clear);
  s.materials.push_back(mirror);
  add_cornell_area_light(s);
  s.spheres.push_back({"SphereFrontRight", "glass", kSphereFrontRight, kSphereRadius});
  s.spheres.push_back({"SphereBackLeft", "mirror", kSphereBackLeft, kSphereRadius});
  s.camera = course_camera(s, {0, 0, 1});
  return s;
}

// A box of `half` extents about `centre`, turned `yaw_degrees` about +y, as
// six lone quads (one mesh each), so that the loader's rule for lone quads
// (their normals reversed) makes each face look out of the box: each is
// wound with its right-hand normal pointing in.
inline void add_block(Scene& s, const std::string& name, const std::string& material, V3 centre, V3 half,
                      double yaw_degrees) {
  const V3 x{half.x, 0, 0}, y{0, half.y, 0}, z{0, 0, half.z};
  // Each face: its outward offset n from the centre and two edges t1, t2
  // with t1 x t2 along n.
  const struct {
    const char* tag;
    V3 n, t1, t2;
  } faces[] = {{"px", x, y, z}, {"nx", -1.0 * x, z, y}, {"py", y, z, x},
               {"ny", -1.0 * y, x, z}, {"pz", z, x, y}, {"nz", -1.0 * z, y, x}};
  for (const auto& f : faces) {
    const auto at = [&](double a, double b) { return centre + rotate_y(f.n + a * f.t1 + b * f.t2, yaw_degrees); };
    s.meshes.push_back(quad(name + "_" + f.tag, material, at(-1, -1), at(-1, 1), at(1, 1), at(1, -1),
                            -1.0 * rotate_y(f.n, yaw_degrees)));
  }
}

// Part 6's second glass scene: a glass block (index 1.5) turned 30 degrees,
// 1 mm above the floor (resting on it, its bottom would lie in the floor's
// plane, and which face a ray hits there would depend on the BVH's order:
// correct BVHs would render it differently), front left, with a diffuse
// sphere behind it to the right.
// Unlike a sphere, a block has total internal reflection: a ray that
// entered by its top or a side meets another side beyond the critical
// angle (41.8 degrees), so its faces seen through one another mirror the
// room.
inline Scene cb_glass_block() {
  Scene s;
  s.file = "CBglass_block.dae";
  s.purpose = "Cornell box with the CGL area light, a glass block (index 1.5) turned 30 degrees "
              "(front left) and a diffuse sphere (back right)";
  add_cornell_box(s);
  s.materials.push_back(glass("glass", 1.5));
  s.materials.push_back(diffuse("lambertian", {0.8, 0.8, 0.8}));
  add_cornell_area_light(s);
  add_block(s, "block", "glass", {-0.3, 0.301, 0.2}, {0.25, 0.3, 0.25}, 30);
  s.spheres.push_back({"SphereBackRight", "lambertian", {0.4, 0.3, -0.3}, kSphereRadius});
  s.camera = course_camera(s, {0, 0, 1});
  return s;
}

// An analytic test: a 2 x 2 diffuse square (albedo 0.5) in the plane y = 0
// under a 0.5 x 0.5 area light of radiance 1 centred 1 unit above it, facing
// down. Only the plane is geometry; the light is not visible to camera rays.
inline Scene plane_arealight() {
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
inline Scene sphere_ambient() {
  Scene s;
  s.file = "sphere_ambient.dae";
  s.purpose = "diffuse sphere (albedo 0.5, radius 0.5) at the origin under an ambient "
              "light of radiance 1; for exact tests";
  s.materials.push_back(diffuse("sphere", {0.5, 0.5, 0.5}));
  s.spheres.push_back({"Sphere", "sphere", {0, 0, 0}, 0.5});
  s.lights.push_back(ambient_light());
  s.camera = course_camera(s, {0, 0, 1});
  return s;
}

// Grading scenes: each shows one thing that the standard scenes hide.

// Part 1: primitives listed nearest first, overlapping in view, so that an
// intersection routine which lets a later (farther) primitive overwrite an
// earlier (nearer) hit shows. Brute force tests the triangles in file
// order, then the spheres: quad A (front) is listed before quad B, which it
// partly hides, and both before the back wall; sphere S1 (front) is listed
// before sphere S2, which it partly hides; S2 also lies partly behind quad
// B, a triangle tested before it.
inline Scene depth_order() {
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

// Part 3: two area lights and two point lights, each pair of different
// sizes, colours and places, so that sampling only one light of a kind,
// averaging the lights instead of summing them, or sampling a delta light
// -l times all show.
inline Scene cb_lights() {
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

// Part 7: the spheres of CBspheres_lambertian.dae in metal, the front
// right one rough gold (microfacet alpha 0.25), the back left one smoother
// copper (alpha 0.05). Also the microfacet side of the renderer's speed
// comparison (instructors/bench/material_speed.sh).
inline Scene cb_spheres_microfacet() {
  Scene s;
  s.file = "CBspheres_microfacet.dae";
  s.purpose = "Cornell box with the CGL area light, a rough gold sphere (front right, microfacet alpha 0.25) "
              "and a copper one (back left, alpha 0.05)";
  add_cornell_box(s);
  s.materials.push_back(gold("gold", 0.25));
  s.materials.push_back(copper("copper", 0.05));
  add_cornell_area_light(s);
  s.spheres.push_back({"SphereFrontRight", "gold", kSphereFrontRight, kSphereRadius});
  s.spheres.push_back({"SphereBackLeft", "copper", kSphereBackLeft, kSphereRadius});
  s.camera = course_camera(s, {0, 0, 1});
  return s;
}

// Part 9's depth of field: five diffuse spheres of different colours in a
// diagonal row from the front right to the back left of the box, their
// centres 0.5 apart in depth (z = 0.7 ... -0.7), so that a focus stack
// (-d at each sphere's distance, 4.1 ... 5.5) moves the sharp one back.
inline Scene cb_spheres_dof() {
  Scene s;
  s.file = "CBspheres_dof.dae";
  s.purpose = "Cornell box with the CGL area light and five diffuse spheres in a row receding from the camera "
              "(part 9: depth of field)";
  add_cornell_box(s);
  add_cornell_area_light(s);
  const Rgb colours[5] = {{0.8, 0.3, 0.2}, {0.8, 0.7, 0.2}, {0.3, 0.7, 0.3}, {0.2, 0.5, 0.8}, {0.6, 0.3, 0.7}};
  for (int i = 0; i < 5; ++i) {
    const std::string name = "dof" + std::to_string(i);
    s.materials.push_back(diffuse(name, colours[i]));
    const double r = 0.16;
    s.spheres.push_back({"Sphere" + std::to_string(i), name, {0.6 - 0.3 * i, r, 0.7 - 0.35 * i}, r});
  }
  s.camera = course_camera(s, {0, 0, 1});
  return s;
}

}  // namespace scenegen
