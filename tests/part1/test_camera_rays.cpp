// Part 1, task 1: generate_ray.
#include <catch2/catch.hpp>
#include <cmath>

#include "stages/part1_raytracing/camera_rays.h"

using namespace pt;

namespace {
void check_dir(const Vec3& d, const Vec3d& expected) {
  const Vec3d e = normalize(expected);
  INFO("direction " << d.x << " " << d.y << " " << d.z << ", expected " << e.x << " " << e.y << " " << e.z);
  // The conventions, and the likely slip when one component has the wrong sign.
  const bool flipped_y = std::fabs(d.y + e.y) < 1e-5 && std::fabs(e.y) > 1e-3 && std::fabs(d.x - e.x) < 1e-5;
  const bool flipped_x = std::fabs(d.x + e.x) < 1e-5 && std::fabs(e.x) > 1e-3 && std::fabs(d.y - e.y) < 1e-5;
  INFO((flipped_y   ? "Hint: only y's sign is wrong: the image would be upside down. (x, y) = (0, 0) is the "
                      "bottom-left of the image, y grows upward. "
        : flipped_x ? "Hint: only x's sign is wrong: the image would be mirrored. x grows to the right. "
                    : "Hint: ")
       << "The camera-space sensor point is ((2x - 1) tan(hFov / 2), (2y - 1) tan(vFov / 2), -1), fields of view "
          "in degrees, turned into world space by the camera's axes (cam.to_world) and normalised.");
  CHECK(norm(d) == Approx(1.0f).epsilon(1e-6));
  CHECK(d.x == Approx(e.x).margin(1e-6));
  CHECK(d.y == Approx(e.y).margin(1e-6));
  CHECK(d.z == Approx(e.z).margin(1e-6));
}
}  // namespace

TEST_CASE("camera rays: centre and corners of a 90 x 90 degree camera", "[part1][camera]") {
  Camera cam;  // at the origin looking down -Z, up +Y
  cam.hfov_deg = 90;
  cam.vfov_deg = 90;
  cam.near_clip = 0.25;
  cam.far_clip = 77;
  const Ray c = generate_ray(cam, 0.5, 0.5);
  check_dir(c.d, {0, 0, -1});
  CHECK(c.o == Vec3(0, 0, 0));
  CHECK(c.min_t == 0.25f);
  CHECK(c.max_t == 77.0f);
  check_dir(generate_ray(cam, 0, 0).d, {-1, -1, -1});  // bottom-left
  check_dir(generate_ray(cam, 1, 0).d, {1, -1, -1});   // bottom-right
  check_dir(generate_ray(cam, 0, 1).d, {-1, 1, -1});   // top-left
  check_dir(generate_ray(cam, 1, 1).d, {1, 1, -1});    // top-right
}

TEST_CASE("camera rays follow the camera's position and orientation", "[part1][camera]") {
  Camera cam;
  cam.hfov_deg = 60;
  cam.vfov_deg = 40;
  cam.look_at(Vec3d(3, 1, 0), Vec3d(0, 1, 0), Vec3d(0, 1, 0));  // looking down -X
  const Ray c = generate_ray(cam, 0.5, 0.5);
  CHECK(c.o == Vec3(3, 1, 0));
  check_dir(c.d, {-1, 0, 0});
  // Right edge of the image points toward -Z when looking down -X with +Y up.
  const double th = std::tan(30 * M_PI / 180);
  check_dir(generate_ray(cam, 1, 0.5).d, {-1, 0, -th});
  const double tv = std::tan(20 * M_PI / 180);
  check_dir(generate_ray(cam, 0.5, 1).d, {-1, tv, 0});
}

TEST_CASE("camera rays: the -r crop rule keeps pixel directions", "[part1][camera]") {
  // A pixel of a 400x300 render points where the same pixel of the centred
  // 400x300 window of the 800x600 render points.
  Camera full;
  full.fit_course_frame(49.13434, 37.8495);
  full.look_at(Vec3d(0, 0.75, 4.8), Vec3d(0, 0.75, 0), Vec3d(0, 1, 0));
  Camera crop = full;
  crop.set_resolution(400, 300);
  for (auto [x, y] : {std::pair{0.0, 0.0}, {400.0, 300.0}, {123.5, 77.25}}) {
    const Ray a = generate_ray(crop, x / 400, y / 300);
    const Ray b = generate_ray(full, (x + 200) / 800, (y + 150) / 600);
    CHECK(a.d.x == Approx(b.d.x).margin(1e-6));
    CHECK(a.d.y == Approx(b.d.y).margin(1e-6));
    CHECK(a.d.z == Approx(b.d.z).margin(1e-6));
  }
}
