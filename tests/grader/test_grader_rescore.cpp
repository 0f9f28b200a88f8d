// grader rescore (command_rescore.cpp) on a real grading run of the fake
// student: the signatures it makes again from the kept renders are the
// graded ones, they follow the renders, and the graded folder is never
// written over.
#include <catch2/catch.hpp>
#include <filesystem>
#include <string>
#include <vector>

#include "common/image_io.h"
#include "tests/grader/grading_sandbox.h"
#include "tests/support.h"

using namespace pt::test::grading;
using Catch::Matchers::Contains;
using pt::test::JsonValue;

// The catalogue of known bugs is remade from rescored gradings when the
// signature gains a figure: a rescore must give what grading gives.
TEST_CASE("rescore: the kept renders give the graded signatures again, into another folder, the graded one untouched") {
  Sandbox sb;
  const std::vector<std::string> names = {"good", "negative_roundoff", "crash"};
  for (const std::string& n : names) sb.add_case(n, 20);
  sb.make_references();
  const std::string graded = sb.path("graded"), out = sb.path("rescored");
  check_finished(sb.grade("by_scene", graded), 1);
  const std::string before = slurp(graded + "/cases/good/result.json");
  const Run r = run_program({grader_exe(), "rescore", graded, "-o", out, "--cases", sb.cases(), "--references",
                             sb.refs()}, {});
  check_finished(r, 0);
  CHECK_THAT(r.out, Contains("2 case signatures made again, 1 kept as graded"));  // crash has no image
  CHECK(slurp(graded + "/cases/good/result.json") == before);
  for (const std::string& n : names) {
    INFO(n);
    const JsonValue a = parse_json_file(graded + "/cases/" + n + "/result.json");
    const JsonValue b = parse_json_file(out + "/graded/cases/" + n + "/result.json");
    CHECK(b.at("verdict").string == a.at("verdict").string);
    CHECK(b.at("score").number == a.at("score").number);
    const auto& sa = a.at("signature").object;
    const auto& sb_ = b.at("signature").object;
    REQUIRE(sb_.size() == sa.size());
    for (const auto& [key, value] : sa) CHECK(sb_.at(key).number == Approx(value.number).margin(1e-9));
    if (n != "crash") CHECK(sa.count("ratio_cell_1_1") == 1);
  }
  // The figures come from the kept renders: halve them, and the image's
  // ratio is halved, everywhere; the verdict and score stay as graded.
  const std::string dimmed = sb.path("dimmed");
  std::filesystem::copy(graded, dimmed, std::filesystem::copy_options::recursive);
  int halved = 0;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dimmed + "/cases/good"))
    if (e.path().filename() == "render.pfm") {
      pt::ImageBuffer img = pt::read_pfm(e.path().string());
      for (pt::Color& c : img.pixels) c = c * 0.5f;
      pt::write_pfm(e.path().string(), img);
      ++halved;
    }
  REQUIRE(halved > 0);
  check_finished(run_program({grader_exe(), "rescore", dimmed, "-o", out, "--cases", sb.cases(), "--references",
                              sb.refs()}, {}), 0);
  const JsonValue d = parse_json_file(out + "/dimmed/cases/good/result.json");
  CHECK(d.at("verdict").string == "passed");
  CHECK(d.at("signature").at("mean_ratio").number == Approx(0.5));
  CHECK(d.at("signature").at("ratio_cell_1_1").number == Approx(0.5));
  // Never over the graded folder itself.
  const Run over = run_program({grader_exe(), "rescore", graded, "-o", sb.path(""), "--cases", sb.cases(),
                                "--references", sb.refs()}, {});
  check_finished(over, 2);
  CHECK_THAT(over.err, Contains("not over it"));
}
