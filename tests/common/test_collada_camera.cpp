// Tests of the scene's camera: the field of view from xfov, yfov and
// aspect_ratio, the course's placement rule and the fallback without a
// camera.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "common/camera.h"
#include "tests/common/collada_documents.h"
#include "common/math_constants.h"

using Catch::Matchers::Contains;
using namespace pt::test::dae;

namespace {
double deg(double r) { return r * 180.0 / pt::kPiDouble; }
double rad(double d) { return d * pt::kPiDouble / 180.0; }
}  // namespace

TEST_CASE("camera field of view from xfov, yfov and aspect_ratio", "[collada][camera]") {
  struct Case {
    const char* name;
    std::string perspective;
    double hfov, vfov;  // after the 4:3 fit
  };
  const double t30 = std::tan(rad(30));
  const std::vector<Case> cases = {
      // xfov 60 with aspect 2: yfov is narrower than 4:3 allows, so it widens.
      {"xfov + aspect", "<xfov>60</xfov><aspect_ratio>2</aspect_ratio>", 60, deg(2 * std::atan(t30 * 0.75))},
      // yfov 60 with aspect 1: xfov too narrow for 4:3, widened.
      {"yfov + aspect", "<yfov>60</yfov><aspect_ratio>1</aspect_ratio>", deg(2 * std::atan(t30 * 4 / 3)), 60},
      // Both given: both used (here already 4:3 exactly).
      {"xfov + yfov", "<xfov>60</xfov><yfov>" + std::to_string(deg(2 * std::atan(t30 * 0.75))) + "</yfov>", 60,
       deg(2 * std::atan(t30 * 0.75))},
      // Only xfov: aspect 4:3 assumed.
      {"xfov alone", "<xfov>60</xfov>", 60, deg(2 * std::atan(t30 * 0.75))},
      {"yfov alone", "<yfov>60</yfov>", deg(2 * std::atan(t30 * 4 / 3)), 60},
  };
  for (const Case& c : cases) {
    SECTION(c.name) {
      Doc d = triangle_doc();
      d.cameras = camera("cam", c.perspective);
      d.nodes += node("<translate>0 0 5</translate>", "<instance_camera url=\"#cam\"/>");
      const Loaded l = load(d);
      CHECK(l.warnings.empty());
      CHECK(l.scene.camera.hfov_deg == Approx(c.hfov).epsilon(1e-6));
      CHECK(l.scene.camera.vfov_deg == Approx(c.vfov).epsilon(1e-6));
      CHECK(l.scene.camera.near_clip == 0.001);
      CHECK(l.scene.camera.far_clip == 1000.0);
    }
  }
}

TEST_CASE("camera placement follows the course's rule", "[collada][camera]") {
  // Bounds of the triangle: centre (0.5, 0.5, 0), extent length sqrt(2).
  Doc d = triangle_doc();
  d.cameras = camera("cam", "<xfov>45</xfov><aspect_ratio>1.5</aspect_ratio><znear>0.25</znear><zfar>50</zfar>");
  const double dist = 1.5 * std::sqrt(2.0);
  SECTION("the node's translation sets the direction, not the position") {
    d.nodes += node("<translate>0 0 5</translate>", "<instance_camera url=\"#cam\"/>");
    const Loaded l = load(d);
    check_vec(l.scene.camera.position, 0.5, 0.5, dist);
    check_vec(l.scene.camera.target, 0.5, 0.5, 0);
    CHECK(l.scene.camera.near_clip == 0.25);
    CHECK(l.scene.camera.far_clip == 50.0);
  }
  SECTION("the point one unit ahead, read as a direction from the origin") {
    // Camera at (3,0,0) looking along -X: one unit ahead is (2,0,0).
    d.nodes += node("<translate>3 0 0</translate><rotate>0 1 0 90</rotate>", "<instance_camera url=\"#cam\"/>");
    const Loaded l = load(d);
    check_vec(l.scene.camera.position, 0.5 + dist, 0.5, 0);
    check_vec(l.scene.camera.axis_z, 1, 0, 0);  // looks along -X
  }
  SECTION("the first camera in document order is used") {
    d.cameras += camera("cam2", "<xfov>80</xfov>");
    d.nodes += node("", node("<translate>0 0 -5</translate>", "<instance_camera url=\"#cam2\"/>")) +
               node("<translate>0 0 5</translate>", "<instance_camera url=\"#cam\"/>");
    const Loaded l = load(d);
    check_vec(l.scene.camera.position, 0.5, 0.5, -dist);
    CHECK(l.scene.camera.hfov_deg == Approx(80));
  }
}

TEST_CASE("no camera: documented fallback with a warning", "[collada][camera]") {
  const Loaded l = load(triangle_doc());
  CHECK(has_warning(l, "<visual_scene id=\"Scene\">", "no camera"));
  check_vec(l.scene.camera.position, 0.5, 0.5, 1.5 * std::sqrt(2.0));
  check_vec(l.scene.camera.axis_z, 0, 0, 1);  // looking toward -Z
  CHECK(l.scene.camera.hfov_deg == Approx(50));
  CHECK(l.scene.camera.vfov_deg == Approx(deg(2 * std::atan(std::tan(rad(25)) * 0.75))));
  CHECK(l.scene.camera.near_clip == 0.001);
  CHECK(l.scene.camera.far_clip == 1000.0);
}

TEST_CASE("an aspect ratio that leaves no field of view is refused (fuzz finding)", "[collada][camera][errors]") {
  for (const char* aspect : {"1e-320", "1e-300"}) {
    SECTION(aspect) {
      Doc d = triangle_doc();
      d.cameras = camera("cam", std::string("<xfov>49.13</xfov><aspect_ratio>") + aspect + "</aspect_ratio>");
      d.nodes += node("<translate>0 0 5</translate>", "<instance_camera url=\"#cam\"/>");
      CHECK_THAT(error_of(d), Contains("<perspective>") && Contains("field of view"));
    }
  }
  SECTION("a field of view too narrow to fit the frame") {
    Doc d = triangle_doc();
    d.cameras = camera("cam", "<xfov>1e-320</xfov><yfov>1e-320</yfov>");
    d.nodes += node("<translate>0 0 5</translate>", "<instance_camera url=\"#cam\"/>");
    CHECK_THAT(error_of(d), Contains("<perspective>") && Contains("field of view"));
  }
}

TEST_CASE("fov_across: the field of view across the other side of a frame", "[collada][camera]") {
  // 90 degrees across a side: tan 45 = 1, so across a side half as long,
  // 2 atan(1/2).
  CHECK(pt::fov_across(90, 0.5) == Approx(deg(2 * std::atan(0.5))));
  CHECK(pt::fov_across(50, 1) == Approx(50));
  // There and back.
  CHECK(pt::fov_across(pt::fov_across(60, 0.75), 4.0 / 3.0) == Approx(60));
  // The course's 4:3 frame: xfov 50 gives yfov 2 atan(tan(25 deg) * 3/4).
  CHECK(pt::fov_across(50, 0.75) == Approx(deg(2 * std::atan(std::tan(rad(25)) * 0.75))));
}
