// Image conversion and files: the course's 8-bit curve, the rate colour
// map, orientation, PFM round trips, atomic writes, sets of outputs
// written all or nothing, and the check of output paths.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <limits>

#include "common/image_io.h"
#include "tests/support.h"

using namespace pt;

TEST_CASE("8-bit conversion is floor(255 clamp((sqrt2 L)^(1/2.2)))", "[image]") {
  CHECK(radiance_to_byte(0.0f) == 0);
  CHECK(radiance_to_byte(-1.0f) == 0);
  CHECK(radiance_to_byte(std::numeric_limits<float>::quiet_NaN()) == 0);
  CHECK(radiance_to_byte(std::numeric_limits<float>::infinity()) == 255);
  CHECK(radiance_to_byte(1.0f) == 255);
  CHECK(radiance_to_byte(0.7072f) == 255);  // just above 1/sqrt(2)
  CHECK(radiance_to_byte(0.7070f) == 254);
  // (sqrt2 * 0.5/sqrt2)^(1/2.2) = 0.5^(1/2.2) = 0.72974 -> floor(186.08) = 186
  CHECK(radiance_to_byte(float(0.5 / std::sqrt(2.0))) == 186);
  // Every byte value is reachable and the map is monotone.
  int prev = 0;
  for (int i = 0; i <= 1000; ++i) {
    const int b = radiance_to_byte(i / 1000.0f);
    CHECK(b >= prev);
    prev = b;
  }
}

TEST_CASE("rate colours run blue -> green -> red linearly", "[image]") {
  uint8_t c[3];
  rate_to_rgb(0.0f, c);
  CHECK((c[0] == 0 && c[1] == 0 && c[2] == 255));
  rate_to_rgb(0.5f, c);
  CHECK((c[0] == 0 && c[1] == 255 && c[2] == 0));
  rate_to_rgb(1.0f, c);
  CHECK((c[0] == 255 && c[1] == 0 && c[2] == 0));
  rate_to_rgb(0.25f, c);
  CHECK((c[0] == 0 && c[1] == 128 && c[2] == 128));
  rate_to_rgb(0.75f, c);
  CHECK((c[0] == 128 && c[1] == 128 && c[2] == 0));
  rate_to_rgb(2.0f, c);  // clamped
  CHECK((c[0] == 255 && c[1] == 0 && c[2] == 0));
  CHECK(rate_image_path("out/a.png") == "out/a_rate.png");
  CHECK(rate_image_path("noext") == "noext_rate.png");
}

TEST_CASE("PNG rows are flipped: pixel (0,0) is the bottom-left", "[image]") {
  test::TempDir dir;
  ImageBuffer img(3, 2);
  img.at(0, 0) = Color(1.0f, 0.0f, 0.0f);  // bottom-left red
  img.at(2, 1) = Color(0.0f, 0.0f, 1.0f);  // top-right blue
  const std::string path = dir.file("o.png");
  write_png(path, img);
  test::Png png;
  REQUIRE(test::read_png(path, &png));
  REQUIRE(png.width == 3);
  REQUIRE(png.height == 2);
  const auto px = [&](int x, int row) { return &png.rgb[(size_t(row) * 3 + x) * 3]; };
  CHECK(px(0, 1)[0] == 255);  // bottom row of the file holds y = 0
  CHECK(px(0, 1)[2] == 0);
  CHECK(px(2, 0)[2] == 255);  // top row holds y = 1
  CHECK(px(2, 0)[0] == 0);
}

TEST_CASE("rate PNG shows samples / max", "[image]") {
  test::TempDir dir;
  ImageBuffer img(2, 1);
  img.samples = {8, 4};
  write_rate_png(dir.file("r.png"), img, 8);
  test::Png png;
  REQUIRE(test::read_png(dir.file("r.png"), &png));
  CHECK((png.rgb[0] == 255 && png.rgb[1] == 0 && png.rgb[2] == 0));
  CHECK((png.rgb[3] == 0 && png.rgb[4] == 255 && png.rgb[5] == 0));
}

TEST_CASE("PFM round trip is bit-exact", "[image]") {
  test::TempDir dir;
  ImageBuffer img(5, 3);
  for (size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = Color(i * 0.1f, -1.5f, 1e20f / (i + 1));
  write_pfm(dir.file("a.pfm"), img);
  const ImageBuffer back = read_pfm(dir.file("a.pfm"));
  REQUIRE(back.width == 5);
  REQUIRE(back.height == 3);
  for (size_t i = 0; i < img.pixels.size(); ++i) CHECK(back.pixels[i] == img.pixels[i]);
  test::write_text(dir.file("bad.pfm"), "P6\n1 1\n255\n");
  CHECK_THROWS_WITH(read_pfm(dir.file("bad.pfm")), Catch::Contains("bad.pfm"));
  test::write_text(dir.file("short.pfm"), "PF\n4 4\n-1\nabc");
  CHECK_THROWS_WITH(read_pfm(dir.file("short.pfm")), Catch::Contains("truncated"));
}

TEST_CASE("writes are atomic: nothing is left behind on success or failure", "[image]") {
  test::TempDir dir;
  write_file_atomically(dir.file("x.bin"), {1, 2, 3});
  CHECK(test::list_dir(dir.path()) == std::vector<std::string>{"x.bin"});
  CHECK_THROWS_WITH(write_file_atomically(dir.file("no/such/dir/x.bin"), {1}), Catch::Contains("no/such/dir"));
  CHECK(test::list_dir(dir.path()) == std::vector<std::string>{"x.bin"});
}

TEST_CASE("a set of output files is written all or nothing", "[image]") {
  test::TempDir dir;
  const std::vector<uint8_t> bytes = {'o', 'k'};
  SECTION("all renamed into place on commit, no temporary left") {
    AtomicFileSet files;
    files.add(dir.file("a.png"), bytes);
    files.add(dir.file("b.pfm"), bytes);
    CHECK_FALSE(test::file_exists(dir.file("a.png")));  // nothing in place before the commit
    files.commit();
    CHECK(test::list_dir(dir.path()).size() == 2);
    CHECK(test::file_exists(dir.file("a.png")));
    CHECK(test::file_exists(dir.file("b.pfm")));
  }
  SECTION("a set dropped before its commit leaves nothing") {
    {
      AtomicFileSet files;
      files.add(dir.file("a.png"), bytes);
    }
    CHECK(test::list_dir(dir.path()).empty());
  }
  SECTION("a failing add leaves nothing") {
    {
      AtomicFileSet files;
      files.add(dir.file("a.png"), bytes);
      CHECK_THROWS_WITH(files.add(dir.file("missing/b.pfm"), bytes), Catch::Contains("missing/b.pfm"));
    }
    CHECK(test::list_dir(dir.path()).empty());
  }
  SECTION("a rename failing in the commit removes the files already renamed") {
    std::filesystem::create_directory(dir.file("c.json"));
    std::filesystem::create_directory(dir.file("c.json/inner"));  // a folder that is not empty cannot be replaced
    AtomicFileSet files;
    files.add(dir.file("a.png"), bytes);
    files.add(dir.file("c.json"), bytes);
    CHECK_THROWS_WITH(files.commit(), Catch::Contains("c.json"));
    const auto left = test::list_dir(dir.path());
    CHECK(left == std::vector<std::string>{"c.json"});
  }
}

TEST_CASE("output paths are checked before anything is written", "[image]") {
  test::TempDir dir;
  CHECK_NOTHROW(check_output_path(dir.file("new.png")));
  test::write_text(dir.file("old.png"), "x");
  CHECK_NOTHROW(check_output_path(dir.file("old.png")));  // replaced by the write
  std::filesystem::create_directory(dir.file("folder.png"));
  CHECK_THROWS_WITH(check_output_path(dir.file("folder.png")), Catch::Contains("folder.png") && Catch::Contains("folder"));
  CHECK_THROWS_WITH(check_output_path(dir.file("none/x.png")), Catch::Contains("none") && Catch::Contains("does not exist"));
  CHECK_THROWS_WITH(check_output_path(dir.file(std::string(252, 'n') + ".png")), Catch::Contains("cannot write"));
  CHECK_THROWS_WITH(check_output_path("/dev/null"), Catch::Contains("not a regular file"));
  CHECK_THROWS(check_output_path(""));
  // The probe leaves nothing behind.
  const auto left = test::list_dir(dir.path());
  CHECK(left.size() == 2);
}
