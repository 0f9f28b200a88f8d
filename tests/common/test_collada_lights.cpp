// Tests of lights: area, point, directional and ambient lights placed by
// their node, and the lights that are skipped.
#include <catch2/catch.hpp>

#include <string>

#include "tests/common/collada_documents.h"

using namespace pt::test::dae;

TEST_CASE("area light: centre, edge vectors and direction from the node transform", "[collada][lights]") {
  Doc d = triangle_doc();
  d.lights = light("L", "<point><color>1 1 1</color></point>", "<area><color>3 4 5</color></area>");
  d.nodes += node("<translate>0 2 0</translate><rotate>1 0 0 -90</rotate><scale>0.5 0.25 1</scale>",
                  instance_light("L"));
  const Loaded l = load(d);
  REQUIRE(l.scene.lights.size() == 1);
  const pt::Light& a = l.scene.lights[0];
  CHECK(a.type == pt::LightType::Area);  // the CGL profile wins over technique_common
  check_vec(a.radiance, 3, 4, 5);
  check_vec(a.position, 0, 2, 0);
  check_vec(a.dim_x, -0.5, 0, 0);
  check_vec(a.dim_y, 0, 0, -0.25);
  check_vec(a.direction, 0, -1, 0);
}

TEST_CASE("point light: position, intensity and attenuation", "[collada][lights]") {
  Doc d = triangle_doc();
  d.lights = light("P",
                   "<point><color>1 2 3</color><constant_attenuation>0.5</constant_attenuation>"
                   "<linear_attenuation>0.25</linear_attenuation>"
                   "<quadratic_attenuation>0.125</quadratic_attenuation></point>") +
             light("Q", "<point><color>1 1 1</color></point>");
  d.nodes += node("<translate>1 2 3</translate>", instance_light("P") + instance_light("Q"));
  const Loaded l = load(d);
  REQUIRE(l.scene.lights.size() == 2);
  const pt::Light& p = l.scene.lights[0];
  CHECK(p.type == pt::LightType::Point);
  check_vec(p.position, 1, 2, 3);
  check_vec(p.radiance, 1, 2, 3);
  CHECK(p.constant_attenuation == Approx(0.5));
  CHECK(p.linear_attenuation == Approx(0.25));
  CHECK(p.quadratic_attenuation == Approx(0.125));
  // Defaults: no fall-off.
  const pt::Light& q = l.scene.lights[1];
  CHECK(q.constant_attenuation == 1);
  CHECK(q.linear_attenuation == 0);
  CHECK(q.quadratic_attenuation == 0);
}

TEST_CASE("directional light uses the node's rotation only", "[collada][lights]") {
  Doc d = triangle_doc();
  d.lights = light("D", "<directional><color>0.5 0.5 0.5</color></directional>");
  SECTION("with translation and scale in the transform") {
    d.nodes += node("<translate>10 20 30</translate><rotate>1 0 0 -90</rotate><scale>2 2 2</scale>",
                    instance_light("D"));
    const Loaded l = load(d);
    REQUIRE(l.scene.lights.size() == 1);
    CHECK(l.scene.lights[0].type == pt::LightType::Directional);
    check_vec(l.scene.lights[0].direction, 0, -1, 0);
    check_vec(l.scene.lights[0].radiance, 0.5, 0.5, 0.5);
  }
  SECTION("in a <matrix> with a Z_UP file") {
    d.up_axis = "Z_UP";
    // Local -Z is (0.6, 0, -0.8) in file space: world (-0.6, -0.8, 0).
    d.nodes += node("<matrix>0.8 0 -0.6 7  0 1 0 8  0.6 0 0.8 9  0 0 0 1</matrix>", instance_light("D"));
    const Loaded l = load(d);
    check_vec(l.scene.lights.at(0).direction, -0.6, -0.8, 0);
  }
}

TEST_CASE("ambient light keeps its colour, spot and unknown lights are skipped with a warning",
          "[collada][lights]") {
  Doc d = triangle_doc();
  d.lights = light("A", "<ambient><color>0.1 0.2 0.3</color></ambient>") +
             light("S", "<spot><color>1 1 1</color></spot>") + light("U", "<laser><color>1 1 1</color></laser>");
  d.nodes += node("", instance_light("A") + instance_light("S") + instance_light("U"));
  const Loaded l = load(d);
  REQUIRE(l.scene.lights.size() == 1);
  CHECK(l.scene.lights[0].type == pt::LightType::Ambient);
  check_vec(l.scene.lights[0].radiance, 0.1, 0.2, 0.3);
  CHECK(has_warning(l, "<light id=\"S\">", "spot"));
  CHECK(has_warning(l, "<light id=\"U\">", "unknown light type <laser>"));
}
