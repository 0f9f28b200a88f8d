// The grader's statistics and file formats, on synthetic data.
#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <random>
#include <sstream>

#include "grader/src/case_list.h"
#include "grader/src/grade.h"
#include "grader/src/reports.h"
#include "grader/src/image_files.h"
#include "common/image_io.h"
#include "common/json.h"
#include "grader/src/scoring.h"
#include "tests/support.h"

using namespace grader;

namespace {

ImageBuffer constant(int w, int h, float v) {
  ImageBuffer img(w, h);
  for (pt::Color& p : img.pixels) p = pt::Color(v);
  return img;
}

// Channel c of pixel (x, row), rows counted from the top.
float& top(ImageBuffer& img, int x, int row, int c) { return img.at(x, img.height - 1 - row)[c]; }

// One "render": the mean plus Gaussian noise of the given variance (drawn
// row by row from the top).
ImageBuffer noisy(const ImageBuffer& mean, double variance, double bias, std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, std::sqrt(variance));
  ImageBuffer img = mean;
  for (int row = 0; row < img.height; ++row)
    for (int x = 0; x < img.width; ++x)
      for (int c = 0; c < 3; ++c) top(img, x, row, c) = float(top(img, x, row, c) + bias + n(rng));
  return img;
}

}  // namespace

TEST_CASE("Sidak level and normal threshold match tabulated values", "[grader]") {
  CHECK(sidak_level(0.01, 1) == Approx(0.01));
  CHECK(sidak_level(0.01, 10000) == Approx(1.00503e-6).epsilon(1e-4));
  CHECK(normal_two_sided_threshold(0.05) == Approx(1.959964).epsilon(1e-5));
  CHECK(normal_two_sided_threshold(0.01) == Approx(2.575829).epsilon(1e-5));
  CHECK(normal_two_sided_threshold(1e-6) == Approx(4.891638).epsilon(1e-5));
}

// alpha = 0.01 per image and test kind; 200 images; at most 6 failures
// (P(Binomial(200, 0.01) > 6) < 0.005), seeded.
TEST_CASE("Renders drawn from the reference distribution pass (false-failure rate)", "[grader]") {
  const ImageBuffer mean = constant(64, 48, 0.5f);
  const ImageBuffer var = constant(64, 48, 0.01f);
  std::mt19937_64 rng(184);
  int failures = 0;
  for (int i = 0; i < 200; ++i) failures += !score_image(noisy(mean, 0.01, 0.0, rng), mean, var, 100000, {}).passed;
  CHECK(failures <= 6);
}

TEST_CASE("A bias of one standard deviation is caught by the block test, not the pixel test", "[grader]") {
  const ImageBuffer mean = constant(64, 48, 0.5f);
  const ImageBuffer var = constant(64, 48, 0.01f);
  std::mt19937_64 rng(7);
  const ImageScore s = score_image(noisy(mean, 0.01, 0.1, rng), mean, var, 100000, {});
  CHECK_FALSE(s.passed);
  CHECK(s.blocks_failed > s.blocks_tested / 2);
  // Per pixel a 1-sigma shift is invisible at a Sidak threshold near 4.8.
  CHECK(s.channels_failed < s.channels_tested / 400);
}

TEST_CASE("Without the block and mean tests the same bias passes: they are what catch it", "[grader]") {
  const ImageBuffer mean = constant(64, 48, 0.5f);
  const ImageBuffer var = constant(64, 48, 0.01f);
  std::mt19937_64 rng(7);
  ScoreOptions o;
  o.block_test = false;
  o.mean_test = false;
  CHECK(score_image(noisy(mean, 0.01, 0.1, rng), mean, var, 100000, o).passed);
}

// A render 8 % darker than the reference, with pixels so noisy (sd = the
// mean) that 8x8 blocks hardly show it (block z = 0.08 * 8 = 0.64 against
// a threshold near 3.9): the image mean is 0.08 * sqrt(12288) = 8.9
// standard errors off. 20 seeded images; the block test alone lets at
// least 18 of them through (it fails one in ~25 at this bias).
TEST_CASE("A bias spread thinly over a noisy image fails the image-mean test, where blocks miss it", "[grader]") {
  const ImageBuffer mean = constant(128, 96, 0.5f);
  const ImageBuffer var = constant(128, 96, 0.25f);
  std::mt19937_64 rng(14);
  ScoreOptions blocks_only;
  blocks_only.mean_test = false;
  int missed_by_blocks = 0;
  for (int i = 0; i < 20; ++i) {
    const ImageBuffer c = noisy(mean, 0.25, -0.04, rng);
    const ImageScore s = score_image(c, mean, var, 100000, {});
    CHECK(s.mean_failed);
    CHECK_FALSE(s.passed);
    CHECK(s.max_mean_z() > 5.0);
    missed_by_blocks += score_image(c, mean, var, 100000, blocks_only).passed;
  }
  CHECK(missed_by_blocks >= 18);
}

TEST_CASE("A deterministic image tolerates round-off and a few edge pixels, not a 3 % shading error", "[grader]") {
  const ImageBuffer mean = constant(100, 100, 0.25f);
  const ImageBuffer var = constant(100, 100, 0.0f);
  ScoreOptions o;
  o.deterministic = true;
  o.block_test = o.mean_test = false;
  ImageBuffer c = mean;
  for (int i = 0; i < 20; ++i) top(c, i, 0, 0) = 1.0f;  // 20 of 30000 channels (0.07%): edge pixels
  CHECK(score_image(c, mean, var, 2, o).passed);
  for (int i = 0; i < 100; ++i) top(c, i, 1, 1) = 1.0f;  // 120 of 30000 (0.4%)
  CHECK_FALSE(score_image(c, mean, var, 2, o).passed);
  // Float round-off of a different but correct computation passes.
  ImageBuffer d = mean;
  for (pt::Color& p : d.pixels) p = p * (1.0f + 3e-6f);
  CHECK(score_image(d, mean, var, 2, o).channels_failed == 0);
  // A systematic 3 % error (0.0075 here) fails every channel, where the z
  // test's variance floor (sd 0.01) would have let it through.
  ImageBuffer e = mean;
  for (pt::Color& p : e.pixels) p = p * 1.03f;
  const ImageScore s = score_image(e, mean, var, 2, o);
  CHECK(s.channels_failed == s.channels_tested);
  CHECK_FALSE(s.passed);
  ScoreOptions z;
  z.block_test = z.mean_test = false;
  CHECK(score_image(e, mean, var, 2, z).passed);
}

TEST_CASE("A pixel whose reference variance is a hole takes its neighbours' variance", "[grader]") {
  const ImageBuffer mean = constant(16, 16, 0.1f);
  ImageBuffer var = constant(16, 16, 0.04f);
  top(var, 8, 8, 0) = 0.0f;  // a rare path never seen there by the reference renders
  ImageBuffer c = mean;
  top(c, 8, 8, 0) = 0.6f;    // 2.5 sigma of its neighbours: an ordinary draw
  ScoreOptions o;
  o.block_test = false;
  const ImageScore s = score_image(c, mean, var, 100, o);
  CHECK(s.channels_failed == 0);
}

TEST_CASE("relMSE of noise alone is near its expected value", "[grader]") {
  const ImageBuffer mean = constant(64, 48, 0.5f);
  const ImageBuffer var = constant(64, 48, 0.01f);
  std::mt19937_64 rng(3);
  const ImageScore s = score_image(noisy(mean, 0.01, 0.0, rng), mean, var, 100000, {});
  CHECK(s.relmse == Approx(s.relmse_expected).epsilon(0.05));
}

TEST_CASE("Sample-rate colours decode back to the rate within one 8-bit step", "[grader]") {
  ImageBuffer rgb(101, 1);
  for (int i = 0; i <= 100; ++i) {
    uint8_t c[3];
    pt::rate_to_rgb(i / 100.0f, c);
    for (int k = 0; k < 3; ++k) rgb.at(i, 0)[k] = c[k];
  }
  const ImageBuffer rate = rate_from_colors(rgb);
  for (int i = 0; i <= 100; ++i) CHECK(rate.at(i, 0)[0] == Approx(i / 100.0).margin(1.0 / 255));
}

TEST_CASE("PFM images round-trip through the image type the renderer and the grader share", "[grader]") {
  pt::test::TempDir dir;
  ImageBuffer img(3, 2);
  for (size_t i = 0; i < img.pixels.size() * 3; ++i) img.pixels[i / 3][int(i % 3)] = float(i) * 0.5f;
  pt::write_pfm(dir.file("a.pfm"), img);
  const ImageBuffer back = pt::read_pfm(dir.file("a.pfm"));
  REQUIRE(back.width == 3);
  REQUIRE(back.height == 2);
  CHECK(back.pixels == img.pixels);
}

TEST_CASE("JSON: values, escapes and errors with offsets", "[grader]") {
  const Json j = pt::parse_json(R"({"a": [1, 2.5, -3e2], "s": "x\"y\\n\u0041", "t": true, "n": null, "o": {"k": 1}})", "t");
  CHECK(j.get("a")->array.size() == 3);
  CHECK(j.get("a")->array[2].number == -300.0);
  CHECK(j.str("s") == "x\"y\\nA");
  CHECK(j.flag("t"));
  CHECK(j.get("o")->num("k") == 1.0);
  CHECK(j.num("missing", 7.0) == 7.0);
  CHECK_THROWS_WITH(pt::parse_json("{\"a\": }", "f.json"), Catch::Contains("f.json") && Catch::Contains("offset"));
  CHECK_THROWS(pt::parse_json("[1, 2", "f.json"));
  CHECK(pt::parse_json(pt::json_quote("a\"b\n\x01"), "q").string == "a\"b\n\x01");
  CHECK(pt::json_number(std::nan("")) == "null");
}

TEST_CASE("The case list rejects malformed lines naming file and line", "[grader]") {
  pt::test::TempDir dir;
  const auto check = [&](const std::string& text, const std::string& expected) {
    std::ofstream(dir.file("cases.txt")) << text;
    CHECK_THROWS_WITH(read_cases(dir.file("cases.txt")), Catch::Contains("cases.txt:2") && Catch::Contains(expected));
  };
  const std::string ok = "a 1 image 1 30 CBempty.dae -r 16 12\n";
  check(ok + "a 1 image 1 30 CBempty.dae\n", "duplicate");
  check(ok + "b 1 shiny 1 30 CBempty.dae\n", "unknown kind");
  check(ok + "b 10 image 1 30 CBempty.dae\n", "part must be 1..9");
  check(ok + "b 0 image 1 30 CBempty.dae\n", "part must be 1..9");
  check(ok + "b 1 image 1 30 CBempty.dae -f x.png\n", "set by the grader");
  check(ok + "b 1 image 1\n", "expected");
  check(ok + "b 1 image 1 -5 CBempty.dae\n", "timeout");
}

TEST_CASE("A case's digest changes with its options, so stale references are refused", "[grader]") {
  pt::test::TempDir dir;
  std::ofstream(dir.file("cases.txt")) << "a 3 image 1 30 CBempty.dae -s 4\nb 3 image 1 30 CBempty.dae -s 8\n";
  const auto cases = read_cases(dir.file("cases.txt"));
  REQUIRE(cases.size() == 2);
  CHECK(case_digest(cases[0]) != case_digest(cases[1]));
  CHECK(case_command(cases[0]) == "--part 3 -s 4 CBempty.dae");
}

TEST_CASE("One deviant block passes as a lone outlier, but two deviant blocks fail", "[grader]") {
  const ImageBuffer mean = constant(64, 48, 0.5f);
  const ImageBuffer var = constant(64, 48, 0.01f);
  ImageBuffer c = mean;
  // Every pixel of block (0, 0) shifted by 1.5 sigma: block z = 12.
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) top(c, x, y, 0) += 0.15f;
  ImageScore s = score_image(c, mean, var, 100000, {});
  CHECK(s.distinct_blocks_failed == 1);
  CHECK(s.passed);
  for (int y = 0; y < 8; ++y)
    for (int x = 16; x < 24; ++x) top(c, x, y, 1) += 0.15f;
  s = score_image(c, mean, var, 100000, {});
  CHECK(s.distinct_blocks_failed == 2);
  CHECK_FALSE(s.passed);
}

TEST_CASE("The terminal table keeps its columns apart for long times and large time ratios", "[grader]") {
  std::vector<CaseResult> rs(3);
  const double seconds[] = {1.25, 123.5, 9.0}, ratios[] = {0.5, 12345.0, -1};
  for (int i = 0; i < 3; ++i) {
    rs[size_t(i)].c.name = "case_" + std::to_string(i);
    rs[size_t(i)].c.part = i + 1;
    rs[size_t(i)].max_score = 2;
    rs[size_t(i)].verdict = Verdict::Failed;
    rs[size_t(i)].message = "why";
    rs[size_t(i)].seconds = seconds[i];
    rs[size_t(i)].speed_ratio = ratios[i];
  }
  const std::string table = terminal_table(rs);
  std::istringstream in(table);
  std::string header, line;
  std::getline(in, header);
  const size_t time_end = header.find(" time ") + 5, ratio_end = header.find("time ratio") + 10;
  REQUIRE(header.find("speed") == std::string::npos);  // named for what it is
  const std::string cells[3][2] = {{"1.2 s", "0.50x"}, {"123.5 s", "12345x"}, {"9.0 s", "-"}};
  for (int i = 0; i < 3; ++i) {
    REQUIRE(std::getline(in, line));
    INFO(line);
    // Right-aligned under their headers, at least two spaces apart.
    CHECK(line.substr(time_end - cells[i][0].size(), cells[i][0].size()) == cells[i][0]);
    CHECK(line.substr(ratio_end - cells[i][1].size(), cells[i][1].size()) == cells[i][1]);
    CHECK(line.substr(time_end, 2) == "  ");
  }
}

TEST_CASE("A deterministic image's summary says nothing of blocks it never tested", "[grader]") {
  const ImageBuffer mean = constant(8, 8, 0.25f);
  ScoreOptions o;
  o.deterministic = true;
  o.block_test = o.mean_test = false;
  const ImageScore s = score_image(mean, mean, constant(8, 8, 0.0f), 2, o);
  CHECK(s.passed);
  CHECK_THAT(s.summary(), !Catch::Contains("block") && Catch::Contains("round-off"));
}

// A sample-rate image of an open scene: the reference's pixels stopped at
// the first batch (rate 0.25) in every one of its runs, so their variance is
// 0, and a correct render still takes one batch more at 1 % of them
// (what calibration measured on the cow, where half the correct renders
// failed). One batch step of slack per pixel passes that; a pixel three
// steps off (it never stopped) still fails, and so does the image when a
// quarter of its pixels never stop.
TEST_CASE("Rate images: one batch more at scattered pixels passes with one step of slack, never stopping fails",
          "[grader]") {
  // The reference as its runs estimate it in the long run: a step of 0.25
  // with probability 0.01 (most pixels' own estimate is 0, which the
  // neighbourhood rule repairs only in part).
  const ImageBuffer mean = constant(160, 120, 0.2525f), var = constant(160, 120, float(0.0625 * 0.01 * 0.99));
  ScoreOptions ro;
  ro.variance_floor = 1e-3;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  ImageBuffer one_more = constant(160, 120, 0.25f);
  for (int p = 0; p < 160 * 120; ++p)  // row by row from the top
    if (u(rng) < 0.01)
      for (int c = 0; c < 3; ++c) top(one_more, p % 160, p / 160, c) = 0.5f;
  CHECK_FALSE(score_image(one_more, mean, var, 100, ro).passed);  // without slack: dozens of |z| = 7.9 pixels
  ro.pixel_slack = 0.25;
  CHECK(score_image(one_more, mean, var, 100, ro).passed);

  ImageBuffer never_stops = one_more;
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 160; ++x)
      for (int c = 0; c < 3; ++c) top(never_stops, x, y, c) = 1.0f;
  const ImageScore s = score_image(never_stops, mean, var, 100, ro);
  CHECK_FALSE(s.passed);
  CHECK(s.channels_failed >= 30 * 160 * 3);
}
