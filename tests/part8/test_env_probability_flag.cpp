// Part 8 through the command line: --env-probability's picture of where a
// render samples the map (uniform over the sphere before part 8, part 8's
// distributions from it on). In part 8's tests, not the command line's:
// it needs part 8's functions, and a part's check must not fail on a part
// that comes after it.
#include <catch2/catch.hpp>
#include <cstdlib>
#include <string>

#include "tests/support.h"

using namespace pt;

TEST_CASE("the env-probability flag writes where the render samples the map, uniform before part 8",
          "[cli][part8]") {
  test::TempDir dir;
  test::write_text(dir.file("tiny.dae"), test::kTinyTriangleScene);
  const std::string sky = test::project_scene("sky_sun.exr");
  for (const char* part : {"7", "8"}) {
    INFO("--part " << part);
    const auto r = test::run_pathtracer(
        {"--part", part, "-r", "8", "6", "-e", sky, "--env-probability", "p.png", "-f", "o.png", "tiny.dae"},
        dir.path());
    INFO("stderr: " << r.err);
    REQUIRE(r.exit_code == 0);
    CHECK(r.err.empty());
    test::Png png;
    REQUIRE(test::read_png(dir.file("p.png"), &png));
    REQUIRE(png.width == 512u);  // sky_sun.exr is 512 x 256
    REQUIRE(png.height == 256u);
    const auto grey = [&](unsigned x, unsigned y) { return int(png.rgb[3 * (size_t(y) * png.width + x)]); };
    int brightest = 0;
    unsigned bx = 0, by = 0;
    for (unsigned y = 0; y < png.height; ++y)
      for (unsigned x = 0; x < png.width; ++x)
        if (grey(x, y) > brightest) brightest = grey(x, y), bx = x, by = y;
    if (std::string(part) == "7") {
      for (unsigned y = 0; y < png.height; y += 17) CHECK(grey(0, y) == grey(300, y));
      CHECK(grey(0, 0) < grey(0, 64));
      CHECK(grey(0, 64) < grey(0, 127));
      CHECK(grey(0, 255) < grey(0, 191));
      // At the equator a texel covers pi/2 times the average texel's share,
      // 10^(log10(pi/2)): grey (0.196 + 3) / 6 of 255.
      CHECK(brightest == grey(0, 127));
      CHECK(std::abs(brightest - 136) <= 1);
    } else {
      CHECK(brightest == 255);  // the sun: over 1000 times the average texel's probability
      CHECK(by < 128);          // above the horizon
      CHECK(grey(bx, 200) < grey(bx, 100));  // the ground is darker than the sky
    }
  }
}
