// Part 9: the thin lens, against the geometry of focus worked out here.
//
// In camera space the lens is the disk of radius R at the origin and the
// plane of focus is z = -f. The ray from lens point L through the focus
// point of image point s (s on the sensor plane z = -1, in tan units) is
// L + t (s f - L). It passes through the point Q = (0, 0, -z0) on the axis
// when s = L (1/f - 1/z0) (for any L): a point at the focal distance
// (z0 = f) is seen through one image point only, and a point at another
// depth through the image points of a disk of radius R |1/f - 1/z0|, that
// is screen_dist R |1/f - 1/z0| pixels (the circle of confusion).
//
// Statistics: one chi-square test (alpha = 0.01; 1,000,000 rays; 8 rings
// of equal area by 16 sectors of the lens disk; fixed seed) of the ray
// origins being uniform over the lens. The other checks are exact within
// float round-off.
//
// Deliberate bug (planted in a scratch copy) -> tests here that failed on it:
//   lens radius R u1 instead of R sqrt(u1)           -> rays start on the lens, focus, uniform
//   focus point on the plane z = -1, not z = -f      -> rays pass through the focus point, focus
//   ray aimed at the focus point from the lens's     -> rays pass through the focus point, focus
//     centre (direction not from the lens point)
//   lens point not turned into world space           -> rays start on the lens (turned camera)
//   focus point focal_distance along the normalised  -> rays pass through the focus point, focus;
//     pinhole ray (a sphere, not the plane)             the failure says so
//   -b applied before part 9                         -> the render gives the lens from part 9 on
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "common/rng.h"
#include "pathtracer/render_job.h"
#include "stages/part1_raytracing/camera_rays.h"
#include "stages/part9_depth_of_field/thin_lens.h"
#include "tests/statistics/analytic_scenes.h"
#include "tests/statistics/hypothesis_tests.h"
#include "tests/statistics/special_functions.h"

using namespace pt;
using namespace pt::test;

namespace {

// A camera at `eye` looking at `at`, 200 x 150 pixels, lens radius R and
// focal distance f.
Camera lens_camera(const Vec3d& eye, const Vec3d& at, double R, double f) {
  Camera cam;
  aim_camera(cam, eye, at, 30.0, 200, 150);
  cam.lens_radius = R;
  cam.focal_distance = f;
  return cam;
}

// Camera-space coordinates of a world point.
Vec3d to_camera(const Camera& cam, const Vec3d& p) {
  const Vec3d d = p - cam.position;
  return Vec3d(dot(d, cam.axis_x), dot(d, cam.axis_y), dot(d, cam.axis_z));
}

// Normalised image coordinates of the sensor point s (tan units).
void image_point(const Camera& cam, double sx, double sy, double* x, double* y) {
  *x = (sx / std::tan(cam.hfov_deg * M_PI / 360.0) + 1) / 2;
  *y = (sy / std::tan(cam.vfov_deg * M_PI / 360.0) + 1) / 2;
}

// Distance from point q to the ray's line, in camera space.
double distance_to_ray(const Camera& cam, const Ray& r, const Vec3d& q_world) {
  const Vec3d o = to_camera(cam, Vec3d(r.o.x, r.o.y, r.o.z));
  const Vec3d d = normalize(Vec3d(dot(Vec3d(r.d.x, r.d.y, r.d.z), cam.axis_x), dot(Vec3d(r.d.x, r.d.y, r.d.z), cam.axis_y),
                                  dot(Vec3d(r.d.x, r.d.y, r.d.z), cam.axis_z)));
  const Vec3d q = to_camera(cam, q_world) - o;
  return norm(q - d * dot(q, d));
}

}  // namespace

TEST_CASE("thin-lens rays start on the lens disk and pass through the pinhole ray's point on the plane of focus",
          "[part9][lens]") {
  const Camera cam = lens_camera(Vec3d(0.3, 0.8, 4.0), Vec3d(-0.2, 0.5, 0.0), 0.25, 3.7);
  Rng rng(90);
  for (int i = 0; i < 5000; ++i) {
    const double x = rng.uniform(), y = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
    const Ray r = generate_ray_for_thin_lens(cam, x, y, u1, u2);
    REQUIRE(std::fabs(norm(r.d) - 1.0f) < 1e-5f);
    CHECK(r.min_t == float(cam.near_clip));
    CHECK(r.max_t == float(cam.far_clip));
    const Vec3d o = to_camera(cam, Vec3d(r.o.x, r.o.y, r.o.z));
    REQUIRE(std::fabs(o.z) < 1e-5);
    REQUIRE(std::hypot(o.x, o.y) <= cam.lens_radius * (1 + 1e-5));
    {
      INFO("u1 " << u1 << ", u2 " << u2 << ": the ray starts at (" << o.x << ", " << o.y << ") on the lens, radius "
                 << std::hypot(o.x, o.y) << ", expected " << cam.lens_radius * std::sqrt(u1)
                 << ". Hint: the lens point is (r cos phi, r sin phi, 0) with r = lens_radius sqrt(u1) and phi = 2 pi "
                    "u2: the square root makes the points uniform over the disk's area (r = lens_radius u1 crowds "
                    "them at the centre), and u1 and u2 are uniform numbers in [0, 1), not a radius and an angle.");
      REQUIRE(std::hypot(o.x, o.y) == Approx(cam.lens_radius * std::sqrt(u1)).margin(1e-5));
    }
    // The pinhole ray meets the plane of focus at t = f / cos.
    const Ray pin = generate_ray(cam, x, y);
    const Vec3d pd(pin.d.x, pin.d.y, pin.d.z);
    const double cos_axis = -dot(pd, cam.axis_z);
    const Vec3d focus = cam.position + pd * (cam.focal_distance / cos_axis);
    const Vec3d along_ray = cam.position + pd * cam.focal_distance;
    INFO("the pinhole ray meets the plane of focus at (" << focus.x << ", " << focus.y << ", " << focus.z
         << "); your ray passes " << distance_to_ray(cam, r, focus) << " from it. "
         << (distance_to_ray(cam, r, along_ray) < 2e-5
                 ? "Hint: your ray aims at the point focal_distance along the pinhole ray: that is a sphere, not "
                   "the plane of focus. The plane is z = -focal_distance in camera space: scale the unnormalised "
                   "sensor point ((2x - 1) tan(hFov / 2), (2y - 1) tan(vFov / 2), -1) by focal_distance, so that "
                   "its z becomes -focal_distance."
                 : "Hint: in camera space the ray starts at the lens point (z = 0) and passes through the point "
                   "where the pinhole ray meets the plane z = -focal_distance; both turned into world space (the "
                   "origin offset by cam.position), the direction normalised."));
    REQUIRE(distance_to_ray(cam, r, focus) < 2e-5);
  }
  // Without a lens the rays are the pinhole's.
  Camera pinhole = cam;
  pinhole.lens_radius = 0;
  const Ray a = generate_ray_for_thin_lens(pinhole, 0.3, 0.6, 0.9, 0.1), b = generate_ray(pinhole, 0.3, 0.6);
  CHECK(norm(a.o - b.o) < 1e-6f);
  CHECK(norm(a.d - b.d) < 1e-6f);
}

TEST_CASE("a point in focus is seen through one image point, at depth z0 through the circle of confusion",
          "[part9][lens][focus]") {
  const double R = 0.2, f = 4.0;
  const Camera cam = lens_camera(Vec3d(0, 0.75, 4.8), Vec3d(0, 0.75, 0), R, f);
  Rng rng(91);
  for (double z0 : {4.0, 2.5, 6.0, 12.0}) {
    const Vec3d q = cam.position - cam.axis_z * z0;  // on the axis, z0 in front
    const double radius = R * std::fabs(1 / f - 1 / z0);  // in tan units on the sensor
    INFO("depth " << z0 << ": circle of confusion " << 2 * radius * cam.screen_dist << " pixels across");
    double widest = 0;
    for (int i = 0; i < 2000; ++i) {
      const double u1 = i < 8 ? 1.0 - 1e-9 : rng.uniform(), u2 = i < 8 ? i / 8.0 : rng.uniform();
      // The lens point these numbers pick, and the image point whose ray
      // from it passes through q.
      const double rl = R * std::sqrt(u1), phi = 2 * M_PI * u2;
      const double lx = rl * std::cos(phi), ly = rl * std::sin(phi);
      const double sx = lx * (1 / f - 1 / z0), sy = ly * (1 / f - 1 / z0);
      double x, y;
      image_point(cam, sx, sy, &x, &y);
      const Ray r = generate_ray_for_thin_lens(cam, x, y, u1, u2);
      INFO("Hint: every ray from the lens toward a point of the plane of focus must meet the pinhole ray there; if "
           "the test of the plane of focus fails too, fix that first (the plane is z = -focal_distance in camera "
           "space, and the lens radius lens_radius sqrt(u1)).");
      REQUIRE(distance_to_ray(cam, r, q) < 2e-5);
      widest = std::max(widest, std::hypot(sx, sy) * cam.screen_dist);
      if (z0 == f) {
        // In focus: every lens point's ray through q comes from the centre pixel.
        REQUIRE(std::fabs((x - 0.5) * cam.width) < 1e-9);
        REQUIRE(std::fabs((y - 0.5) * cam.height) < 1e-9);
      }
    }
    // The rim of the lens (the first eight samples) reaches the circle's edge.
    CHECK(widest == Approx(radius * cam.screen_dist).epsilon(1e-6).margin(1e-9));
  }
}

TEST_CASE("thin-lens rays start uniformly over the lens disk, chi-square", "[part9][lens][chi2]") {
  const Camera cam = lens_camera(Vec3d(0, 0, 5), Vec3d(0, 0, 0), 0.5, 5.0);
  const int rings = 8, sectors = 16, samples = 1000000;
  std::vector<double> observed(size_t(rings * sectors), 0.0);
  std::vector<double> expected(observed.size(), double(samples) / (rings * sectors));
  Rng rng(92);
  for (int i = 0; i < samples; ++i) {
    const Ray r = generate_ray_for_thin_lens(cam, rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform());
    const Vec3d o = to_camera(cam, Vec3d(r.o.x, r.o.y, r.o.z));
    const double rr = (o.x * o.x + o.y * o.y) / (cam.lens_radius * cam.lens_radius);  // area fraction
    double phi = std::atan2(o.y, o.x);
    if (phi < 0) phi += 2 * M_PI;
    const int a = std::min(rings - 1, int(rr * rings)), b = std::min(sectors - 1, int(phi / (2 * M_PI) * sectors));
    observed[size_t(a * sectors + b)] += 1;
  }
  const ChiSquareResult r = chi_square_test(observed, expected);
  stats_log("lens disk: " + r.describe());
  INFO(r.describe() << ". Hint: lens points uniform over the disk's area need r = lens_radius sqrt(u1) (r = "
                       "lens_radius u1 crowds them at the centre) and phi = 2 pi u2.");
  CHECK(r.p_value >= 0.01);
}

TEST_CASE("the render gives the camera the thin lens from --part 9 on, before, -b leaves a pinhole",
          "[part9][lens][parts]") {
  RenderOptions o;
  o.width = 64;
  o.height = 48;
  o.lens_radius = 0.1;
  o.lens_radius_set = true;
  for (int part = 1; part <= 9; ++part) {
    o.part = part;
    Camera cam;
    configure_camera(cam, o);
    INFO("--part " << part);
    CHECK(cam.lens_radius == 0.1);
    CHECK((cam.thin_lens == nullptr) == (part < 9));
  }
}
