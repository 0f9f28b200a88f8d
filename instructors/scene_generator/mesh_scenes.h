// The scenes built from the pinned third-party meshes (mesh_library.h): the
// bunny and dragon Cornell boxes, the meshedit-like scenes, the bunny under
// an ambient light.
#pragma once
#include <string>

#include "instructors/scene_generator/collada_writer.h"
#include "instructors/scene_generator/mesh_library.h"
#include "instructors/scene_generator/mesh_tools.h"
#include "instructors/scene_generator/scene_model.h"
#include "instructors/scene_generator/scene_parts.h"

namespace scenegen {

// The course's CBbunny, stated in our (unmirrored) box: the bunny stands on
// the floor in the middle of the box, 0.772 tall (its bounding box is about
// 0.78 wide, 0.77 tall and 0.60 deep), its lowest point 2 mm above the
// floor. Our camera looks from +z where the course's file looks from -z at a
// mirrored box; keeping the bunny in its source orientation here gives the
// same view of it as the course's image (head on the left).
inline Scene cb_bunny(MeshLibrary& lib) {
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
inline Scene cb_dragon(MeshLibrary& lib, size_t triangles, const std::string& file, const std::string& purpose) {
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

// Part 7: the dragon of CBdragon.dae, at 50,000 triangles, in gold of
// roughness alpha.
inline Scene cb_dragon_gold(MeshLibrary& lib, double alpha, const std::string& file) {
  Scene s;
  s.file = file;
  s.purpose = "Cornell box with the CGL area light and the Stanford dragon (50,000 triangles) in gold, "
              "microfacet alpha " + num(alpha);
  add_cornell_box(s);
  s.materials.push_back(gold("gold", alpha));
  add_cornell_area_light(s);
  IndexedMesh m = lib.dragon(kSmallDragonTriangles);
  place_on_floor(m, 0, 0, 1.4, 0.002);
  s.meshes.push_back(scene_mesh("dragon", "gold", m, true));
  s.camera = course_camera(s, {0, 0, 1});
  return s;
}

// Part 8: the bunny of CBbunny.dae in copper (alpha 0.1, as the course's
// bunny_microfacet_cu_unlit.dae) on a 1.2 x 1.2 grey pedestal,
// and no light: it is lit by the environment map given with -e
// (sky_sun.exr).
inline Scene bunny_microfacet_envmap(MeshLibrary& lib) {
  Scene s;
  s.file = "bunny_microfacet_envmap.dae";
  s.purpose = "the Stanford bunny (28,576 triangles) in copper (microfacet alpha 0.1) on a grey pedestal, with no "
              "light: render it with an environment map (-e)";
  s.materials.push_back(diffuse("pedestal", {0.25, 0.25, 0.25}));
  s.materials.push_back(copper("copper", 0.1));
  s.meshes.push_back(quad("pedestal", "pedestal", {-0.6, 0, -0.6}, {0.6, 0, -0.6}, {0.6, 0, 0.6}, {-0.6, 0, 0.6},
                          {0, -1, 0}));
  IndexedMesh m = lib.bunny();
  place_on_floor(m, 0, 1, 0.772, 0.002);
  s.meshes.push_back(scene_mesh("bunny", "copper", m, true));
  s.camera = course_camera(s, {0, 0.4, 1});
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
inline Scene open_mesh_scene(const std::string& file, const std::string& purpose, const std::string& name,
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

inline Scene cow(MeshLibrary& lib) {
  return open_mesh_scene("cow.dae", "the cow (5,804 triangles) under a directional light, like the course's meshedit scenes",
                         "cow", lib.cow(), true, 0, {0, 0, 1});
}

inline Scene teapot(MeshLibrary& lib) {
  return open_mesh_scene("teapot.dae",
                         "the Utah teapot (16,256 triangles from its 32 Bezier patches, open) under a directional light",
                         "teapot", lib.teapot(), false, 0, {0, 0.5, 1});
}

inline Scene armadillo(MeshLibrary& lib) {
  return open_mesh_scene("armadillo.dae", "the Stanford armadillo (52,000 triangles) under a directional light",
                         "armadillo", lib.armadillo(), true, 180, {0, 0, 1});
}

// The bunny of CBbunny, same size, on a 2 x 2 diffuse ground square under
// an ambient (uniform sky) light of radiance 1: lighting that hemisphere
// sampling (-H) and light sampling both reach, for comparing them.
inline Scene bunny_ambient(MeshLibrary& lib) {
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
  s.lights.push_back(ambient_light());
  s.camera = course_camera(s, {0, 0.5, 1});
  return s;
}

}  // namespace scenegen
