// The camera's course rules: FOV fit to 800x600, the -r crop rule,
// placement, and the -c settings file.
#include <catch2/catch.hpp>

#include "common/camera.h"
#include "tests/support.h"

using namespace pt;

TEST_CASE("course FOV fit widens the narrow axis to 4:3 and fixes the focal length", "[camera]") {
  Camera cam;
  // The Cornell boxes: xfov 49.13434 with aspect 1.333333.
  const double xfov = 49.13434;
  const double yfov = 2 * std::atan(std::tan(xfov / 2 * M_PI / 180) / 1.333333) * 180 / M_PI;
  cam.fit_course_frame(xfov, yfov);
  CHECK(cam.width == 800);
  CHECK(cam.height == 600);
  CHECK(cam.hfov_deg == Approx(49.134).margin(0.01));
  CHECK(cam.vfov_deg == Approx(37.85).margin(0.01));
  CHECK(cam.screen_dist == Approx(875.0).margin(0.5));

  // A too-narrow horizontal FOV is widened instead.
  Camera tall;
  tall.fit_course_frame(20.0, 40.0);
  CHECK(tall.vfov_deg == Approx(40.0));
  CHECK(std::tan(tall.hfov_deg / 2 * M_PI / 180) / std::tan(tall.vfov_deg / 2 * M_PI / 180) ==
        Approx(4.0 / 3.0));
}

TEST_CASE("resolution (-r) keeps the focal length: 480x360 is a centre crop of the course frame", "[camera]") {
  Camera cam;
  const double xfov = 49.13434;
  cam.fit_course_frame(xfov, 2 * std::atan(std::tan(xfov / 2 * M_PI / 180) / 1.333333) * 180 / M_PI);
  cam.set_resolution(480, 360);
  // CS184-COMPAT.md: Cornell boxes at -r 480 360 are 30.68 x 23.25 degrees.
  CHECK(cam.hfov_deg == Approx(30.68).margin(0.01));
  CHECK(cam.vfov_deg == Approx(23.25).margin(0.01));
  CHECK(cam.width == 480);
  CHECK(cam.height == 360);
}

TEST_CASE("course placement looks at the bounding-box centre from 1.5 |extent| away", "[camera]") {
  Camera cam;
  const BBox box(Vec3(-1, 0, -1), Vec3(1, 1.5f, 1));
  cam.place_course(Vec3d(0, 0, 2), box);
  CHECK(cam.position.x == Approx(0).margin(1e-9));
  CHECK(cam.position.y == Approx(0.75));
  CHECK(cam.position.z == Approx(4.8023).margin(1e-4));
  // Orthonormal right-handed frame looking at the target.
  CHECK(dot(cam.axis_x, cam.axis_y) == Approx(0).margin(1e-12));
  CHECK(dot(cam.axis_x, cam.axis_z) == Approx(0).margin(1e-12));
  CHECK(norm(cross(cam.axis_x, cam.axis_y) - cam.axis_z) == Approx(0).margin(1e-12));
  const Vec3d to_target = normalize(cam.target - cam.position);
  CHECK(dot(to_target, -cam.axis_z) == Approx(1.0));
  CHECK(cam.axis_y.y > 0.99);  // world up stays up
}

TEST_CASE("look_at straight down does not produce NaN axes", "[camera]") {
  Camera cam;
  cam.look_at(Vec3d(0, 5, 0), Vec3d(0, 0, 0), Vec3d(0, 1, 0));
  CHECK(is_finite(cam.axis_x));
  CHECK(is_finite(cam.axis_y));
  CHECK(dot(cam.axis_z, Vec3d(0, 1, 0)) == Approx(1.0));
}

TEST_CASE("camera settings file (-c) is read, and malformed files are rejected", "[camera]") {
  test::TempDir dir;
  const std::string good = dir.file("cam.txt");
  test::write_text(good,
                   "30 20 1.5 0.01 50\n"
                   "1 2 3 0 0 0\n"
                   "0 0 5 1 10\n"
                   "1 0 0 0 1 0 0 0 1\n"
                   "800 600 900\n"
                   "4 0.1\n");
  Camera cam;
  cam.load_settings(good);
  CHECK(cam.hfov_deg == 30);
  CHECK(cam.vfov_deg == 20);
  CHECK(cam.near_clip == Approx(0.01));
  CHECK(cam.far_clip == 50);
  CHECK(cam.position == Vec3d(1, 2, 3));
  CHECK(cam.axis_z == Vec3d(0, 0, 1));
  CHECK(cam.screen_dist == 900);
  CHECK(cam.focal_distance == 4);
  CHECK(cam.lens_radius == Approx(0.1));

  const std::string short_file = dir.file("short.txt");
  test::write_text(short_file, "30 20 1.5 0.01 50\n1 2 3 0 0 0\n");
  REQUIRE_THROWS_WITH(cam.load_settings(short_file), Catch::Contains("short.txt") && Catch::Contains("6 lines"));

  const std::string bad_number = dir.file("bad.txt");
  test::write_text(bad_number, "30 twenty 1.5 0.01 50\n");
  REQUIRE_THROWS_WITH(cam.load_settings(bad_number), Catch::Contains("line 1") && Catch::Contains("twenty"));

  const std::string wrong_count = dir.file("count.txt");
  test::write_text(wrong_count, "30 20 1.5 0.01 50\n1 2 3\n");
  REQUIRE_THROWS_WITH(cam.load_settings(wrong_count), Catch::Contains("line 2") && Catch::Contains("expected 6"));

  REQUIRE_THROWS_WITH(cam.load_settings(dir.file("missing.txt")), Catch::Contains("missing.txt"));
}

TEST_CASE("camera settings file (-c): degenerate axes, non-finite numbers and a bad focal distance are refused",
          "[camera]") {
  test::TempDir dir;
  const std::string lines[6] = {"30 20 1.5 0.01 50", "1 2 3 0 0 0", "0 0 5 1 10", "1 0 0 0 1 0 0 0 1", "800 600 900",
                                "4 0.1"};
  // A file with line `which` (1-based) replaced by `text`.
  auto file_with = [&](int which, const std::string& text) {
    std::string s;
    for (int i = 0; i < 6; ++i) s += (i + 1 == which ? text : lines[i]) + "\n";
    const std::string path = dir.file("cam" + std::to_string(which) + ".txt");
    test::write_text(path, s);
    return path;
  };
  struct Case {
    int line;
    std::string text, needle;
  };
  const std::vector<Case> cases = {
      {4, "0 0 0 0 0 0 0 0 0", "line 4"},          // zero axes
      {4, "1 0 0 0 0 0 0 0 1", "line 4"},          // one zero axis
      {4, "1 0 0 0 1 0 0 0 0", "line 4"},          // another
      {4, "1 0 0 1 0 0 0 0 1", "line 4"},          // two parallel axes
      {4, "2 0 0 0 2 0 0 0 2", "line 4"},          // not unit length: a scaled frame
      {4, "-1 0 0 0 1 0 0 0 1", "line 4"},         // mirrored (left-handed)
      {4, "1 0 0 0 1 0 0 0 nan", "nan"},
      {4, "1 0 0 0 1 0 0 0 inf", "inf"},
      {2, "1 2 nan 0 0 0", "nan"},
      {1, "30 20 1.5 0.01 -inf", "-inf"},
      {6, "0 0.1", "line 6"},                      // focal distance 0
      {6, "-4 0.1", "line 6"},                     // negative focal distance
      {6, "4 -0.1", "line 6"},                     // negative lens radius
      {6, "4 1e999", "1e999"},
  };
  for (const Case& c : cases) {
    INFO("line " << c.line << ": " << c.text);
    Camera cam;
    const std::string path = file_with(c.line, c.text);
    CHECK_THROWS_WITH(cam.load_settings(path), Catch::Contains(path) && Catch::Contains(c.needle));
  }
  // A rotation written with six significant digits is accepted.
  Camera cam;
  cam.load_settings(file_with(4, "0.707107 0 0.707107 0 1 0 -0.707107 0 0.707107"));
  CHECK(cam.axis_x.x == Approx(0.707107));
}
