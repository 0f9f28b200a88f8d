// Tests of values read from XML text (number syntax, ranges) and of the
// form of the loader's messages.
#include <catch2/catch.hpp>

#include <string>

#include "tests/common/collada_documents.h"

using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;
using namespace pt::test::dae;

TEST_CASE("number syntax: signs, bare decimal points, exponents, extreme values", "[collada]") {
  Doc d;
  d.geometries = mesh("g", "+1 .5 -2e0   1E1 5. 1e-400   \n\t0 -.25 +3", 3, polylist("g", "3", "0 1 2"));
  d.nodes = node("", instance_geometry("g"));
  const Loaded l = load(d);
  REQUIRE(l.scene.triangles.size() == 1);
  check_vec(l.scene.triangles[0].p1, 1, 0.5, -2);
  check_vec(l.scene.triangles[0].p2, 10, 5, 0);  // 1e-400 underflows to 0
  check_vec(l.scene.triangles[0].p3, 0, -0.25, 3);
}

TEST_CASE("numbers that overflow single precision are refused, not turned into infinity (fuzz findings)",
          "[collada][errors]") {
  SECTION("a sphere so large that the camera would stand at infinity") {
    Doc d;
    d.geometries = "<geometry id=\"ball\"><extra><technique profile=\"CGL\"><sphere><radius>3.4e38</radius>"
                   "</sphere></technique></extra></geometry>";
    d.nodes = node("", instance_geometry("ball"));
    CHECK_THAT(error_of(d), Contains("<visual_scene id=\"Scene\">") && Contains("too large for single-precision"));
  }
  SECTION("a light colour beyond float range") {
    Doc d = triangle_doc();
    d.lights = light("L", "<point><color>3.5e38 5 5</color></point>");
    d.nodes += node("", instance_light("L"));
    CHECK_THAT(error_of(d), Contains("<color>") && Contains("too large for single precision"));
  }
  SECTION("an attenuation beyond float range") {
    Doc d = triangle_doc();
    d.lights = light("L", "<point><color>1 1 1</color><constant_attenuation>1e39</constant_attenuation></point>");
    d.nodes += node("", instance_light("L"));
    CHECK_THAT(error_of(d), Contains("<constant_attenuation>") && Contains("too large"));
  }
}

TEST_CASE("warnings are one line and start with the file's path", "[collada]") {
  Doc d = triangle_doc();
  d.lights = light("S", "<spot><color>1 1 1</color></spot>");
  d.nodes += node("", instance_light("S"));
  const Loaded l = load(d);
  REQUIRE(l.warnings.size() == 2);  // the spot light and the missing camera
  for (const std::string& w : l.warnings) {
    CHECK_THAT(w, StartsWith(l.path + ": <"));
    CHECK(w.find('\n') == std::string::npos);
  }
}
