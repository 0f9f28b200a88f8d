// The course's own scene files load with the expected contents. The files
// are read from ../shared/cs184-scenes; every test is skipped when that
// folder is absent.
#include <catch2/catch.hpp>

#include <cmath>
#include <initializer_list>
#include <map>
#include <string>
#include <vector>

#include "common/collada.h"
#include "tests/support.h"

namespace {

struct Loaded {
  pt::Scene scene;
  std::vector<std::string> warnings;
};

Loaded load(const std::string& name) {
  const std::string path = pt::test::course_scene(name);
  Loaded l;
  l.scene = pt::load_collada(path, &l.warnings);
  return l;
}

std::map<pt::MaterialType, int> materials_by_type(const pt::Scene& s) {
  std::map<pt::MaterialType, int> m;
  for (const pt::Material& mat : s.materials) ++m[mat.type];
  return m;
}

std::map<pt::LightType, int> lights_by_type(const pt::Scene& s) {
  std::map<pt::LightType, int> m;
  for (const pt::Light& l : s.lights) ++m[l.type];
  return m;
}

template <typename V>
void check_vec(const V& v, double x, double y, double z, double eps = 1e-4) {
  INFO("got (" << v.x << ", " << v.y << ", " << v.z << "), want (" << x << ", " << y << ", " << z << ")");
  CHECK(double(v.x) == Approx(x).margin(eps));
  CHECK(double(v.y) == Approx(y).margin(eps));
  CHECK(double(v.z) == Approx(z).margin(eps));
}

// Properties every loaded course scene has.
void check_common(const Loaded& l) {
  for (const std::string& w : l.warnings) FAIL_CHECK("unexpected warning: " << w);
  for (const pt::Triangle& t : l.scene.triangles) {
    REQUIRE(t.material >= 0);
    REQUIRE(size_t(t.material) < l.scene.materials.size());
    for (const pt::Vec3& n : {t.n1, t.n2, t.n3}) REQUIRE(pt::norm(n) == Approx(1.0f).margin(1e-5));
  }
  for (const pt::Sphere& s : l.scene.spheres) REQUIRE(size_t(s.material) < l.scene.materials.size());
}

// The Cornell box shared by four scenes: walls spanning x, z in [-1, 1],
// y in [0, 1.5], an emissive quad at y = 1.49 and the 49.13 degree camera.
void check_cornell_box(const Loaded& l, double camera_z) {
  const pt::BBox b = l.scene.bounds();
  check_vec(b.lo, -1, 0, -1);
  check_vec(b.hi, 1, 1.5, 1);
  int emissive = 0;
  for (const pt::Triangle& t : l.scene.triangles)
    if (l.scene.materials[size_t(t.material)].is_emissive()) {
      ++emissive;
      CHECK(t.p1.y == Approx(1.49).margin(1e-4));
    }
  CHECK(emissive == 2);

  const pt::Camera& c = l.scene.camera;
  check_vec(c.position, 0, 0.75, camera_z, 1e-3);
  check_vec(c.target, 0, 0.75, 0, 1e-4);
  // xfov 49.13434 with aspect 16:9: the vertical FOV is widened to 4:3.
  CHECK(c.hfov_deg == Approx(49.13434).margin(1e-3));
  CHECK(c.vfov_deg == Approx(37.8493).margin(1e-3));
  CHECK(c.near_clip == Approx(0.1));
  CHECK(c.far_clip == Approx(100));
}

// The CGL area light of the Cornell boxes: 0.6 x 0.8 at y = 1.49, facing down.
void check_area_light(const pt::Light& a) {
  CHECK(a.type == pt::LightType::Area);
  check_vec(a.radiance, 10, 10, 10);
  check_vec(a.position, 0, 1.49, 0, 1e-6);
  check_vec(a.dim_x, 0.6, 0, 0, 1e-6);
  check_vec(a.dim_y, 0, 0, 0.8, 1e-6);
  check_vec(a.direction, 0, -1, 0, 1e-6);
  CHECK(pt::norm(pt::cross(a.dim_x, a.dim_y)) == Approx(0.48));
}

}  // namespace

TEST_CASE("course scene CBempty.dae", "[course]") {
  const Loaded l = load("CBempty.dae");
  check_common(l);
  CHECK(l.scene.triangles.size() == 12);
  CHECK(l.scene.spheres.empty());
  CHECK(l.scene.materials.size() == 6);
  CHECK(materials_by_type(l.scene) ==
        std::map<pt::MaterialType, int>{{pt::MaterialType::Diffuse, 5}, {pt::MaterialType::Emission, 1}});
  check_cornell_box(l, 4.8023);

  CHECK(lights_by_type(l.scene) == std::map<pt::LightType, int>{{pt::LightType::Point, 1}});
  REQUIRE(l.scene.lights.size() == 1);
  const pt::Light& p = l.scene.lights[0];
  check_vec(p.radiance, 5, 5, 5);
  check_vec(p.position, 0, 1.49, 0.004316, 1e-5);
  CHECK(p.constant_attenuation == Approx(1));
  CHECK(p.linear_attenuation == Approx(0));
  CHECK(p.quadratic_attenuation == Approx(0.001599967));

  // Diffuse colours of the walls.
  std::map<std::string, pt::Color> albedo;
  for (const pt::Material& m : l.scene.materials) albedo[m.name] = m.albedo;
  check_vec(albedo.at("leftWall-material"), 0.6, 0.2, 0.2);
  check_vec(albedo.at("rightWall-material"), 0.2, 0.2, 0.6);
  check_vec(albedo.at("floor-material"), 0.6, 0.6, 0.6);
}

TEST_CASE("course scene CBspheres_lambertian.dae", "[course]") {
  const Loaded l = load("CBspheres_lambertian.dae");
  check_common(l);
  CHECK(l.scene.triangles.size() == 12);
  REQUIRE(l.scene.spheres.size() == 2);
  CHECK(materials_by_type(l.scene) ==
        std::map<pt::MaterialType, int>{{pt::MaterialType::Diffuse, 7}, {pt::MaterialType::Emission, 1}});
  check_cornell_box(l, 4.8023);
  // The light has both a technique_common point and a CGL area: area wins.
  CHECK(lights_by_type(l.scene) == std::map<pt::LightType, int>{{pt::LightType::Area, 1}});
  REQUIRE(l.scene.lights.size() == 1);
  check_area_light(l.scene.lights[0]);

  check_vec(l.scene.spheres[0].center, 0.4, 0.3, 0.3, 1e-6);
  check_vec(l.scene.spheres[1].center, -0.4, 0.3, -0.3, 1e-6);
  for (const pt::Sphere& s : l.scene.spheres) {
    CHECK(s.radius == Approx(0.3));
    const pt::Material& m = l.scene.materials[size_t(s.material)];
    CHECK(m.type == pt::MaterialType::Diffuse);
    check_vec(m.albedo, 0.8, 0.8, 0.8);
  }
}

TEST_CASE("course scene CBspheres.dae", "[course]") {
  const Loaded l = load("CBspheres.dae");
  check_common(l);
  CHECK(l.scene.triangles.size() == 12);
  REQUIRE(l.scene.spheres.size() == 2);
  CHECK(materials_by_type(l.scene) == std::map<pt::MaterialType, int>{{pt::MaterialType::Diffuse, 5},
                                                                       {pt::MaterialType::Emission, 1},
                                                                       {pt::MaterialType::Glass, 1},
                                                                       {pt::MaterialType::Mirror, 1}});
  check_cornell_box(l, 4.8023);
  CHECK(lights_by_type(l.scene) == std::map<pt::LightType, int>{{pt::LightType::Area, 1}});
  REQUIRE(l.scene.lights.size() == 1);
  check_area_light(l.scene.lights[0]);

  const pt::Material& glass = l.scene.materials[size_t(l.scene.spheres[0].material)];
  CHECK(glass.name == "refract");
  CHECK(glass.type == pt::MaterialType::Glass);
  check_vec(glass.reflectance, 1, 1, 1);
  check_vec(glass.transmittance, 1, 1, 1);
  CHECK(glass.roughness == 0);
  CHECK(glass.ior == Approx(1.45));
  const pt::Material& chrome = l.scene.materials[size_t(l.scene.spheres[1].material)];
  CHECK(chrome.name == "chrome");
  CHECK(chrome.type == pt::MaterialType::Mirror);
  check_vec(chrome.reflectance, 1, 1, 1);
}

TEST_CASE("course scene CBbunny.dae", "[course]") {
  const Loaded l = load("CBbunny.dae");
  check_common(l);
  // 28,576 bunny triangles + 6 quads of the box: the course's 28,588 primitives.
  CHECK(l.scene.triangles.size() == 28588);
  CHECK(l.scene.num_primitives() == 28588);
  CHECK(l.scene.spheres.empty());
  CHECK(l.scene.materials.size() == 7);
  CHECK(materials_by_type(l.scene) ==
        std::map<pt::MaterialType, int>{{pt::MaterialType::Diffuse, 6}, {pt::MaterialType::Emission, 1}});
  int bunny = 0;
  for (const pt::Triangle& t : l.scene.triangles)
    if (l.scene.materials[size_t(t.material)].name == "Default-material") ++bunny;
  CHECK(bunny == 28576);
  // This file's camera node faces the box from the other side (its box is
  // mirrored by the node transforms), so the course's rule puts it at -z.
  check_cornell_box(l, -4.8023);
  CHECK(lights_by_type(l.scene) == std::map<pt::LightType, int>{{pt::LightType::Area, 1}});
  REQUIRE(l.scene.lights.size() == 1);
  check_area_light(l.scene.lights[0]);
}

TEST_CASE("course scene cow.dae", "[course]") {
  const Loaded l = load("cow.dae");
  check_common(l);
  CHECK(l.scene.triangles.size() == 5856);
  CHECK(l.scene.spheres.empty());
  REQUIRE(l.scene.materials.size() == 1);
  CHECK(l.scene.materials[0].type == pt::MaterialType::Diffuse);
  check_vec(l.scene.materials[0].albedo, 0.48, 0.48, 0.48);

  CHECK(lights_by_type(l.scene) == std::map<pt::LightType, int>{{pt::LightType::Directional, 1}});
  REQUIRE(l.scene.lights.size() == 1);
  const pt::Light& d = l.scene.lights[0];
  CHECK(d.type == pt::LightType::Directional);
  check_vec(d.radiance, 1, 1, 1);
  // Travels away from the light: the negative of the "toward the light"
  // direction (-0.5, 0.7071, 0.5). The course's translation-leaking version
  // would be toward (-0.4706, 0.7463, 0.4706).
  check_vec(d.direction, 0.5, -0.7071068, -0.5, 1e-6);
  CHECK(pt::norm(d.direction) == Approx(1.0f));

  const pt::Camera& c = l.scene.camera;
  check_vec(c.position, 0, -0.039447, 3.253571, 1e-4);
  CHECK(c.hfov_deg == Approx(39.5978).margin(1e-3));
  CHECK(c.vfov_deg == Approx(30.2192).margin(1e-3));
  CHECK(c.near_clip == Approx(0.00999999));
  CHECK(c.far_clip == Approx(10000));
}

TEST_CASE("course scene plane.dae", "[course]") {
  const Loaded l = load("plane.dae");
  check_common(l);
  REQUIRE(l.scene.triangles.size() == 2);
  CHECK(l.scene.spheres.empty());
  REQUIRE(l.scene.materials.size() == 1);
  check_vec(l.scene.materials[0].albedo, 0.6, 0.6, 0.6);
  // A wall in the plane z = -0.9957. Its winding (and its stored normals)
  // face -z, away from the camera and the light; as a lone quad its
  // recomputed normals are reversed, as the course's are, so it faces +z
  // and is lit.
  for (const pt::Triangle& t : l.scene.triangles) {
    CHECK(t.p1.z == Approx(-0.995684).margin(1e-5));
    check_vec(t.n1, 0, 0, 1, 1e-5);
  }

  CHECK(lights_by_type(l.scene) == std::map<pt::LightType, int>{{pt::LightType::Point, 1}});
  REQUIRE(l.scene.lights.size() == 1);
  const pt::Light& p = l.scene.lights[0];
  check_vec(p.position, 0, 1.49, 0, 1e-6);
  check_vec(p.radiance, 1, 1, 1);
  CHECK(p.quadratic_attenuation == Approx(0.001599907));

  check_vec(l.scene.camera.position, 0, 0.25, 2.754316, 1e-4);
  check_vec(l.scene.camera.target, 0, 0.25, -0.995684, 1e-4);
}

TEST_CASE("course Cornell boxes: wall normals face into the box, as in the course", "[course]") {
  // The walls are single quads wound to face out of the box; the course's
  // recomputed normals of such all-boundary meshes are reversed, so they
  // face into the box, where the camera and the light are.
  for (const char* name : {"CBempty.dae", "CBspheres.dae", "CBbunny.dae"}) {
    INFO(name);
    const Loaded l = load(name);
    int floor = 0, ceiling = 0;
    for (const pt::Triangle& t : l.scene.triangles) {
      const std::string& m = l.scene.materials[size_t(t.material)].name;
      if (m == "floor-material") {
        ++floor;
        for (const pt::Vec3& n : {t.n1, t.n2, t.n3}) check_vec(n, 0, 1, 0, 1e-5);
      }
      if (m == "ceiling-material") {
        ++ceiling;
        for (const pt::Vec3& n : {t.n1, t.n2, t.n3}) check_vec(n, 0, -1, 0, 1e-5);
      }
    }
    CHECK(floor == 2);
    CHECK(ceiling == 2);
  }
}
