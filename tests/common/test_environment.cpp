// Environment maps (-e): reading OpenEXR, the latitude-longitude lookup,
// bad files, and the light they cast.
//
// One statistical test (z test, alpha = 0.01, fixed seed): a diffuse plane
// under a uniform sky reflects albedo * L. It catches a wrong sphere pdf
// (e.g. 1 / (2 pi)), a missing cosine, and samples below the plane kept.
#include <ImfRgbaFile.h>
#include <ImfTiledRgbaFile.h>
#include <sys/resource.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>

#include "stages/part1_raytracing/brute_force.h"
#include "stages/part3_direct_lighting/direct_lighting.h"
#include "common/environment.h"
#include "common/rng.h"
#include "common/lights.h"
#include "common/image_io.h"
#include "tests/support.h"

using namespace pt;

namespace {
// Writes a w x h EXR whose texel (x, y) is f(x, y).
template <typename F>
void write_exr(const std::string& path, int w, int h, F f) {
  std::vector<Imf::Rgba> px(size_t(w) * size_t(h));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Color c = f(x, y);
      px[size_t(y * w + x)] = Imf::Rgba(c.x, c.y, c.z, 1.0f);
    }
  Imf::RgbaOutputFile file(path.c_str(), w, h, Imf::WRITE_RGBA);
  file.setFrameBuffer(px.data(), 1, size_t(w));
  file.writePixels(h);
}
}  // namespace

TEST_CASE("environment map: texels are read and looked up by latitude and longitude", "[environment]") {
  test::TempDir dir;
  const std::string path = dir.file("sky.exr");
  write_exr(path, 8, 4, [](int x, int y) { return Color(float(x), float(y), 0.5f); });
  const EnvironmentMap env = load_environment_map(path);
  REQUIRE(env.width == 8);
  REQUIRE(env.height == 4);
  CHECK(env.lookup({0, 1, 0}).y == 0.0f);   // straight up: the top row
  CHECK(env.lookup({0, -1, 0}).y == 3.0f);  // straight down: the bottom row
  // The course's layout: phi = atan2(-z, x) + pi from the left edge.
  const Color ahead = env.lookup({1, 0, 0});  // +X: the centre column, the middle
  CHECK(ahead.x == 4.0f);
  CHECK(ahead.y == 2.0f);
  CHECK(env.lookup({0, 0, 1}).x == 2.0f);       // +Z: one quarter across
  CHECK(env.lookup({0, 0, -1}).x == 6.0f);      // -Z: three quarters across
  CHECK(env.lookup({-1, 0, 0.01f}).x == 0.0f);  // -X: the left edge ...
  CHECK(env.lookup({-1, 0, -0.01f}).x == 7.0f); // ... and the right edge
  CHECK(env.lookup({0, 0, 1}).z == 0.5f);
  int x = -1, y = -1;
  env.texel_of({0, 0, -1}, &x, &y);
  CHECK(x == 6);
  CHECK(y == 2);
}

TEST_CASE("environment map: angles and directions convert both ways by the course's convention", "[environment]") {
  Rng rng(17);
  for (int i = 0; i < 1000; ++i) {
    const float theta = float(M_PI) * (0.001f + 0.998f * rng.uniform()), phi = 2 * float(M_PI) * rng.uniform();
    const Vec3 d = angles_to_direction(theta, phi);
    REQUIRE(std::fabs(norm(d) - 1.0f) < 1e-5f);
    // The course's theta_phi_to_dir: (cos(phi - pi) sin, cos, -sin(phi - pi) sin).
    REQUIRE(d.x == Approx(std::cos(phi - M_PI) * std::sin(theta)).margin(1e-5));
    REQUIRE(d.y == Approx(std::cos(theta)).margin(1e-5));
    REQUIRE(d.z == Approx(-std::sin(phi - M_PI) * std::sin(theta)).margin(1e-5));
    float t = 0, p = 0;
    direction_to_angles(d, &t, &p);
    REQUIRE(t == Approx(theta).margin(1e-4));
    REQUIRE(std::fabs(std::remainder(p - phi, 2 * M_PI)) < 1e-4);
  }
}

TEST_CASE("environment map: missing, malformed and negative files fail naming the file", "[environment]") {
  test::TempDir dir;
  CHECK_THROWS_WITH(load_environment_map(dir.file("none.exr")), Catch::Contains("none.exr"));
  test::write_text(dir.file("text.exr"), "not an exr file");
  CHECK_THROWS_WITH(load_environment_map(dir.file("text.exr")), Catch::Contains("text.exr"));
  write_exr(dir.file("neg.exr"), 2, 2, [](int, int) { return Color(-1.0f, 0.0f, 0.0f); });
  CHECK_THROWS_WITH(load_environment_map(dir.file("neg.exr")), Catch::Contains("negative"));
}

TEST_CASE("a diffuse plane under a uniform environment reflects albedo times its radiance", "[environment]") {
  test::TempDir dir;
  write_exr(dir.file("white.exr"), 16, 8, [](int, int) { return Color(2.0f, 1.0f, 0.5f); });
  Scene s;
  Material m;
  m.albedo = Color(0.5f);
  s.materials.push_back(m);
  Light env;
  env.type = LightType::Environment;
  env.environment = std::make_shared<const EnvironmentMap>(load_environment_map(dir.file("white.exr")));
  s.lights.push_back(env);
  BruteForceIntersector none(s);  // nothing to occlude
  ShadingContext ctx{s, none};
  ctx.light_samples = 1;
  Hit hit;
  hit.t = 1;
  hit.n = Vec3(0, 1, 0);
  hit.material = 0;
  const Ray r({0, 1, 0}, {0, -1, 0});
  for (bool hemisphere : {false, true}) {
    ctx.hemisphere = hemisphere;
    Rng rng(42);
    const int n = 200000;
    double sum = 0, sum2 = 0;
    for (int i = 0; i < n; ++i) {
      const double v = hemisphere ? estimate_direct_lighting_hemisphere(ctx, r, hit, rng).x
                                  : estimate_direct_lighting_importance(ctx, r, hit, rng).x;
      sum += v;
      sum2 += v * v;
    }
    const double mean = sum / n, se = std::sqrt((sum2 / n - mean * mean) / (n - 1));
    INFO((hemisphere ? "hemisphere" : "light sampling") << ": mean " << mean << " se " << se);
    // Expected rho * L = 0.5 * 2 = 1; z critical 2.576 at alpha = 0.01.
    CHECK(std::abs(mean - 1.0) <= 2.576 * se + 1e-9);
  }
}

TEST_CASE("the command line renders with an environment map: the sky is seen and lights the scene",
          "[environment][cli]") {
  test::TempDir dir;
  write_exr(dir.file("sky.exr"), 16, 8, [](int, int) { return Color(0.25f); });
  test::write_text(dir.file("tri.dae"), test::kTinyTriangleScene);
  const auto r = test::run_pathtracer({"--part", "4", "-m", "2", "-s", "16", "-r", "800", "600", "-e", "sky.exr",
                                       "--pfm", "o.pfm", "-f", "o.png", "tri.dae"},
                                      dir.path());
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const ImageBuffer img = read_pfm(dir.file("o.pfm"));
  CHECK(img.at(2, 597).x == Approx(0.25f));  // the corner sees the sky
  // The triangle, lit by the sky over its front hemisphere, reflects
  // albedo * L = 0.5 * 0.25. One pixel at 16 samples has a standard
  // deviation of about 0.04, so average 400 pixels at the centre (standard
  // error about 0.002) and allow 4 standard errors.
  double sum = 0;
  for (int y = 290; y < 310; ++y)
    for (int x = 390; x < 410; ++x) sum += img.at(x, y).x;
  CHECK(sum / 400 == Approx(0.125).margin(0.008));
}

namespace {
std::string read_all(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}

// Rewrites the data window of an EXR file's header to (0,0)-(w-1,h-1).
void set_data_window(const std::string& path, int w, int h) {
  std::string bytes = read_all(path);
  const std::string key = std::string("dataWindow") + '\0' + "box2i" + '\0';
  const size_t at = bytes.find(key);
  REQUIRE(at != std::string::npos);
  const size_t box = at + key.size() + 4;  // after the attribute's size
  const int32_t v[4] = {0, 0, w - 1, h - 1};
  std::memcpy(&bytes[box], v, sizeof v);
  std::ofstream(path, std::ios::binary) << bytes;
}

// Limits this process's address space for the lifetime of the object.
struct AddressSpaceLimit {
  rlimit old{};
  explicit AddressSpaceLimit(rlim_t bytes) {
    getrlimit(RLIMIT_AS, &old);
    const rlimit lim{bytes, old.rlim_max};
    setrlimit(RLIMIT_AS, &lim);
  }
  ~AddressSpaceLimit() { setrlimit(RLIMIT_AS, &old); }
};
}  // namespace

TEST_CASE("environment map: a header claiming a huge image is refused before anything is allocated",
          "[environment]") {
  test::TempDir dir;
  const std::string path = dir.file("huge.exr");
  write_exr(path, 4, 2, [](int, int) { return Color(1.0f); });
  set_data_window(path, 65536, 65536);  // 32 GiB of pixels claimed by a file of a few hundred bytes
  const AddressSpaceLimit limit(rlim_t(2) << 30);
  CHECK_THROWS_WITH(load_environment_map(path), Catch::Contains(path) && Catch::Contains("65536x65536"));
}

TEST_CASE("environment map: a header claiming more pixels than the file can hold is refused", "[environment]") {
  test::TempDir dir;
  const std::string path = dir.file("short.exr");
  // Uncompressed: every pixel is in the file, so 4096 x 4096 needs 128 MB.
  std::vector<Imf::Rgba> px(8, Imf::Rgba(1, 1, 1, 1));
  {
    Imf::RgbaOutputFile file(path.c_str(), 4, 2, Imf::WRITE_RGBA, 1, Imath::V2f(0, 0), 1, Imf::INCREASING_Y,
                             Imf::NO_COMPRESSION);
    file.setFrameBuffer(px.data(), 1, 4);
    file.writePixels(2);
  }
  set_data_window(path, 4096, 4096);
  CHECK_THROWS_WITH(load_environment_map(path), Catch::Contains(path) && Catch::Contains("4096x4096") &&
                                                    Catch::Contains("bytes"));
}

TEST_CASE("environment map: a direction with NaN or infinite components still finds a texel", "[environment]") {
  test::TempDir dir;
  write_exr(dir.file("sky.exr"), 8, 4, [](int x, int y) { return Color(float(x), float(y), 1.0f); });
  const EnvironmentMap env = load_environment_map(dir.file("sky.exr"));
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  for (const Vec3& d : {Vec3(nan, nan, nan), Vec3(inf, 0, 0), Vec3(0, -inf, inf), Vec3(nan, 1, 0), Vec3(0, 0, 0),
                        Vec3(1e38f, 1e38f, -1e38f)}) {
    const Color c = env.lookup(d);
    CHECK(c.z == 1.0f);
    CHECK((c.x >= 0 && c.x <= 7 && c.y >= 0 && c.y <= 3));
  }
}

namespace {
// The offset of the value of header attribute `name` in an EXR file.
size_t attribute_value(const std::string& bytes, const std::string& name, const std::string& type) {
  const std::string key = name + '\0' + type + '\0';
  const size_t at = bytes.find(key);
  REQUIRE(at != std::string::npos);
  return at + key.size() + 4;
}
}  // namespace

TEST_CASE("environment map: malformed header attributes are refused before OpenEXR allocates for them (fuzz findings)",
          "[environment]") {
  test::TempDir dir;
  const std::string good = dir.file("good.exr");
  write_exr(good, 4, 2, [](int, int) { return Color(1.0f); });
  const std::string bytes = read_all(good);
  const AddressSpaceLimit limit(rlim_t(1) << 30);  // a 1.8 GB allocation would fail
  SECTION("an attribute claiming more bytes than the file holds") {
    std::string b = bytes;
    const int32_t size = 1879048192;
    std::memcpy(&b[attribute_value(b, "screenWindowWidth", "float") - 4], &size, 4);
    std::ofstream(dir.file("a.exr"), std::ios::binary) << b;
    CHECK_THROWS_WITH(load_environment_map(dir.file("a.exr")),
                      Catch::Contains("screenWindowWidth") && Catch::Contains("more than the file holds"));
  }
  SECTION("a fixed-size attribute of the wrong size") {
    std::string b = bytes;
    const int32_t size = 11;
    std::memcpy(&b[attribute_value(b, "dataWindow", "box2i") - 4], &size, 4);
    std::ofstream(dir.file("b.exr"), std::ios::binary) << b;
    CHECK_THROWS_WITH(load_environment_map(dir.file("b.exr")),
                      Catch::Contains("dataWindow") && Catch::Contains("not 16"));
  }
  SECTION("a channel list that does not fill its size") {
    std::string b = bytes;
    b[attribute_value(b, "channels", "chlist")] = '\0';  // the list ends at once, but its size says more
    std::ofstream(dir.file("c.exr"), std::ios::binary) << b;
    CHECK_THROWS_WITH(load_environment_map(dir.file("c.exr")), Catch::Contains("channels") && Catch::Contains("malformed"));
  }
}

TEST_CASE("environment map: tiles too large to buffer are refused (fuzz finding)", "[environment]") {
  test::TempDir dir;
  const std::string path = dir.file("tiled.exr");
  std::vector<Imf::Rgba> px(8, Imf::Rgba(1, 1, 1, 1));
  {
    Imf::TiledRgbaOutputFile f(path.c_str(), 4, 2, 4, 4, Imf::ONE_LEVEL, Imf::ROUND_DOWN, Imf::WRITE_RGBA);
    f.setFrameBuffer(px.data(), 1, 4);
    f.writeTiles(0, f.numXTiles() - 1, 0, f.numYTiles() - 1);
  }
  CHECK(load_environment_map(path).width == 4);  // as written, it reads
  std::string b = read_all(path);
  const uint32_t tall = 33554436;
  std::memcpy(&b[attribute_value(b, "tiles", "tiledesc") + 4], &tall, 4);
  std::ofstream(path, std::ios::binary) << b;
  const AddressSpaceLimit limit(rlim_t(1) << 30);
  CHECK_THROWS_WITH(load_environment_map(path), Catch::Contains("tiles of 4x33554436"));
}
