// What a grading run notices across cases (findings.h), on made-up results.
#include <catch2/catch.hpp>

#include <algorithm>

#include "tests/grader/make_case.h"
#include "grader/src/findings.h"
#include "grader/src/hints.h"
#include "grader/src/run_case.h"
#include "grader/src/rules.h"
#include "grader/src/signature.h"

using namespace grader;

namespace {

CaseResult result(const std::string& name, int part, Verdict v, const Signature& sig,
                  std::vector<std::string> options = {}) {
  CaseResult r;
  r.c.name = name;
  r.c.part = part;
  r.c.options = std::move(options);
  r.verdict = v;
  r.signature = sig;
  return r;
}

}  // namespace

TEST_CASE("NaN pixels are reported once, with the first part and case where they appear", "[grader]") {
  const std::vector<CaseResult> rs = {
      result("p1_a", 1, Verdict::Passed, {{"mean_ratio", 1.0}}),
      result("p4_m2", 4, Verdict::Failed, {{"failure_nan", 1}, {"nan_pixels", 40}}),
      result("p3_spheres_light", 3, Verdict::Failed, {{"failure_nan", 1}, {"nan_pixels", 12}}),
  };
  const std::vector<std::string> f = run_findings(rs);
  REQUIRE(f.size() == 1);
  CHECK_THAT(f[0], Catch::StartsWith("NaN pixels first appear in part 3 (p3_spheres_light, 12 pixels; 2 cases in all)"));
  CHECK_THAT(f[0], Catch::Contains("positive pdf"));
  CHECK(run_findings({rs[0]}).empty());
}

TEST_CASE("Part 3 images uniformly half as bright in two cases are reported as self-shadowing", "[grader]") {
  const Signature half = {{"mean_ratio", 0.48}, {"ratio_bright", 0.5}, {"ratio_mid", 0.46}};
  const Signature dark_shadows_only = {{"mean_ratio", 0.6}, {"ratio_bright", 0.98}, {"ratio_mid", 0.5}};
  std::vector<CaseResult> rs = {result("p3_spheres_light", 3, Verdict::Failed, half),
                                result("p3_hemi", 3, Verdict::Failed, half, {"-H"})};
  CHECK(run_findings(rs).empty());  // one light-sampling case: not a pattern; -H does not count
  rs.push_back(result("p3_bunny_light", 3, Verdict::Failed, half));
  const std::vector<std::string> f = run_findings(rs);
  REQUIRE(f.size() == 1);
  CHECK_THAT(f[0], Catch::StartsWith("part 3's images are about half as bright everywhere (p3_spheres_light x0.48, "
                                     "p3_bunny_light x0.48): self-shadowing?"));
  CHECK_THAT(f[0], Catch::Contains("kRayEpsilon") && Catch::Contains("EPS_D"));
  // Dark only in some regions (a missing term, not acne) is not this.
  rs = {result("a", 3, Verdict::Failed, dark_shadows_only), result("b", 3, Verdict::Failed, dark_shadows_only)};
  CHECK(run_findings(rs).empty());
}

// ---- Hints from the known bugs' signatures (hints.h) ----

namespace {

using grader::test::make_case;

const std::vector<Case> kCases = {
    make_case("p1_spheres", 1, "CBspheres_lambertian.dae"), make_case("p1_cow", 1, "cow.dae"),
    make_case("p3_spheres_light", 3, "CBspheres_lambertian.dae"),
    make_case("p3_spheres_hemisphere", 3, "CBspheres_lambertian.dae", {"-H"}),
    make_case("p4_m2", 4, "CBspheres_lambertian.dae", {"-m", "2"}),
    make_case("p4_m5", 4, "CBspheres_lambertian.dae", {"-m", "5"})};

CaseSignature failing(double ratio) {
  CaseSignature c;
  c.failed = true;
  c.figures = {{"mean_ratio", ratio}, {"failed_image", 1}};
  return c;
}

KnownBug bug(const std::string& name, int part, const std::string& function, const std::string& hint,
             BuildSignature cases) {
  KnownBug b;
  b.name = name;
  b.part = part;
  b.function = function;
  b.file = "stages/x.cpp";
  b.readme = "stages/README.md#Section";
  b.hint = hint;
  b.cases = std::move(cases);
  return b;
}

Catalogue catalogue() {
  Catalogue c;
  c.bugs = {bug("emission_twice", 4, "at_least_one_bounce_radiance", "too bright by about {ratio} after two bounces",
                {{"p4_m2", failing(1.9)}, {"p4_m5", failing(2.0)}}),
            bug("no_rr_division", 4, "at_least_one_bounce_radiance", "too dark ({ratio})", {{"p4_m5", failing(0.8)}}),
            bug("hemisphere_pdf", 3, "estimate_direct_lighting_hemisphere", "-H off ({ratio})",
                {{"p3_spheres_hemisphere", failing(0.5)}}),
            bug("sphere_root", 1, "intersect_sphere", "spheres inside out",
                {{"p1_spheres", failing(0.7)}, {"p3_spheres_light", failing(0.6)}, {"p4_m2", failing(0.6)}})};
  return c;
}

}  // namespace

TEST_CASE("Hints: the nearest known bug comes first, in words, with the build's own figures", "[grader]") {
  const Catalogue cat = catalogue();
  const CaseGroups groups = case_groups(kCases);
  const BuildSignature build = {{"p4_m2", failing(1.7)}, {"p4_m5", failing(1.8)}};
  const std::vector<Hint> hints = likely_bugs(build, cat, groups);
  REQUIRE(!hints.empty());
  CHECK(hints[0].bug->name == "emission_twice");
  CHECK_THAT(hints[0].text, Catch::StartsWith("too bright by about x1.8 after two bounces (at_least_one_bounce_radiance "
                                              "in stages/x.cpp; read stages/README.md (\"Section\"); explains "
                                              "p4_m2, p4_m5 (2 of 2 failing cases))"));
  // One hint per function: no_rr_division is the same function.
  for (size_t i = 1; i < hints.size(); ++i) CHECK(hints[i].bug->function != hints[0].bug->function);
  CHECK(signature_distance(cat.bugs[0].cases, cat.bugs[0].cases, groups) == 0.0);
}

TEST_CASE("Hints: none for a build that fails nothing, and a plain 'nothing close' when no bug is near", "[grader]") {
  const Catalogue cat = catalogue();
  std::vector<CaseResult> passing(2);
  passing[0].c = kCases[0];
  passing[0].verdict = Verdict::Passed;
  passing[0].score = passing[0].max_score = 1;
  passing[1] = passing[0];
  passing[1].c = kCases[1];
  CHECK(hint_lines(passing, cat, case_groups(kCases)).empty());

  // A build that fails only the cow, which no known bug does.
  std::vector<CaseResult> odd = passing;
  odd[1].verdict = Verdict::Failed;
  odd[1].score = 0;
  odd[1].signature = {{"failure_crash", 1}};
  const std::vector<std::string> lines = hint_lines(odd, cat, case_groups(kCases));
  REQUIRE(lines.size() == 1);
  CHECK_THAT(lines[0], Catch::StartsWith("Likely cause: no known bug's signature is close"));
}

// A kit with parts 1-5 solved (or a build that has not started part 4):
// the cases it fails stop at a TODO line. An unwritten part is not a bug,
// and a hint would send the student to working code.
TEST_CASE("Hints: none for cases that stopped at a TODO line, while the other failures still get theirs", "[grader]") {
  const Catalogue cat = catalogue();
  std::vector<CaseResult> rs(2);
  rs[0].c = kCases[0];
  rs[1].c = kCases[1];
  for (CaseResult& r : rs) {
    r.verdict = Verdict::Failed;
    r.score = 0;
    r.max_score = 1;
    r.signature = {{"failed_image", 1}, {"failure_todo", 1}};
  }
  CHECK(hint_lines(rs, cat, case_groups(kCases)).empty());
  CHECK(build_signature(rs).empty());
  rs[1].signature = {{"failure_crash", 1}};  // a real failure beside the TODO
  CHECK(build_signature(rs).size() == 1);
  CHECK(hint_lines(rs, cat, case_groups(kCases)).size() == 1);
}

TEST_CASE("Hints: leave-one-out names the right function when another bug of it is near", "[grader]") {
  Catalogue cat = catalogue();
  // A second hemisphere bug like the first: leaving either out, the other names the function.
  cat.bugs.push_back(bug("hemisphere_not_to_world", 3, "estimate_direct_lighting_hemisphere", "-H from the wrong side",
                         {{"p3_spheres_hemisphere", failing(0.6)}}));
  HintRates rates;
  const std::string table = held_out_table(cat, case_groups(kCases), HoldOut::Bug, &rates);
  CHECK_THAT(table, Catch::Contains("| hemisphere_pdf | 3 | estimate_direct_lighting_hemisphere | "
                                    "estimate_direct_lighting_hemisphere"));
  CHECK(rates.function_top3 > 0.5);
  CHECK(rates.part_top3 >= rates.function_top3);
}

// A case of part 3 runs stages 1..3 only: a bug of part 4 cannot fail it,
// however alike its signature.
TEST_CASE("Hints: a bug of a part after the earliest failing case's is not named while a bug that could fail it is near",
          "[grader]") {
  Catalogue cat = catalogue();
  cat.bugs.push_back(bug("bounce_dark", 4, "sample_bounce", "dark",
                         {{"p3_spheres_light", failing(0.6)}, {"p4_m2", failing(0.6)}}));
  const CaseGroups groups = case_groups(kCases);
  const BuildSignature build = {{"p3_spheres_light", failing(0.6)}, {"p4_m2", failing(0.6)}};
  CHECK(earliest_failing_part(build, groups) == 3);
  CHECK(earliest_failing_part({{"p3_spheres_light", CaseSignature{}}}, groups) == 0);  // fails nothing
  // bounce_dark's signature is the build's own, sphere_root's is not.
  REQUIRE(signature_distance(build, cat.bugs.back().cases, groups) == 0.0);
  REQUIRE(signature_distance(build, cat.bugs[3].cases, groups) > 0.0);
  const std::vector<Hint> hints = likely_bugs(build, cat, groups);
  REQUIRE(!hints.empty());
  CHECK(hints[0].bug->name == "sphere_root");
  for (const Hint& h : hints) CHECK(h.bug->part <= 3);
}

// A case can fail by chance: when no bug that could have failed the
// earliest failing case is near, a near bug of a later part still speaks.
TEST_CASE("Hints: a near bug of a later part is named when no bug of the earlier parts is near", "[grader]") {
  Catalogue cat;
  cat.bugs = {bug("hemisphere_pdf", 3, "estimate_direct_lighting_hemisphere", "-H off",
                  {{"p3_spheres_hemisphere", failing(0.5)}}),
              bug("bounce_dark", 4, "sample_bounce", "dark", {{"p3_spheres_light", failing(0.6)}, {"p4_m2", failing(0.6)}})};
  const CaseGroups groups = case_groups(kCases);
  const BuildSignature build = {{"p3_spheres_light", failing(0.6)}, {"p4_m2", failing(0.6)}};
  REQUIRE(signature_distance(build, cat.bugs[0].cases, groups) > kHintDistance);
  const std::vector<Hint> hints = likely_bugs(build, cat, groups);
  REQUIRE(hints.size() == 1);
  CHECK(hints[0].bug->name == "bounce_dark");
}

// A bug of an earlier part usually fails that part's cases too: when every
// failing case is of part 4, a near bug of part 4 is among the hints even if
// bugs of earlier parts are nearer; a far one is not.
TEST_CASE("Hints: the nearest bug of the earliest failing part is among them when it is nearly as near", "[grader]") {
  const BuildSignature build = {{"p4_m2", failing(0.6)}, {"p4_m5", failing(0.6)}};
  const BuildSignature alike = build;
  Catalogue cat;
  cat.bugs = {bug("camera_a", 1, "generate_ray", "a", alike), bug("bvh_b", 2, "BVH::intersect", "b", alike),
              bug("light_c", 3, "estimate_direct_lighting_importance", "c", alike),
              bug("loop_d", 4, "at_least_one_bounce_radiance", "d", {{"p4_m2", failing(0.5)}, {"p4_m5", failing(0.5)}})};
  const CaseGroups groups = case_groups(kCases);
  REQUIRE(earliest_failing_part(build, groups) == 4);
  const double d = signature_distance(build, cat.bugs[3].cases, groups);
  REQUIRE(d > 0.0);
  REQUIRE(d <= kHintSpread);
  std::vector<Hint> hints = likely_bugs(build, cat, groups);
  REQUIRE(hints.size() == 3);
  CHECK(hints[0].bug->name == "camera_a");
  CHECK(hints[1].bug->name == "bvh_b");
  CHECK(hints[2].bug->name == "loop_d");  // in the last place, instead of light_c
  // Far behind the first (beyond the spread), it is not named.
  cat.bugs[3].cases = {{"p4_m2", failing(9.0)}, {"p4_m5", failing(9.0)}};
  REQUIRE(signature_distance(build, cat.bugs[3].cases, groups) > kHintSpread);
  hints = likely_bugs(build, cat, groups);
  REQUIRE(hints.size() == 3);
  for (const Hint& h : hints) CHECK(h.bug->part < 4);
}

TEST_CASE("The catalogue refuses a malformed file, naming it", "[grader]") {
  CHECK_THROWS_WITH(read_catalogue("/nonexistent/known_bugs.json"), Catch::Contains("/nonexistent/known_bugs.json"));
}

TEST_CASE("Hints from one case alone: only bugs that fail that case, nearest first", "[grader]") {
  const Catalogue cat = catalogue();
  const std::vector<Hint> hints =
      likely_bugs_for_case("p4_m2", failing(1.8), cat, case_groups(kCases));
  REQUIRE(!hints.empty());
  CHECK(hints[0].bug->name == "emission_twice");
  CHECK(hints[0].bug == &cat.bugs[0]);  // points into the caller's catalogue
  for (const Hint& h : hints) CHECK(h.bug->name != "hemisphere_pdf");  // passes p4_m2
  CHECK(likely_bugs_for_case("p4_m2", CaseSignature{}, cat, case_groups(kCases)).empty());  // a passing case
}

TEST_CASE("Project 3-2's cases: their groups, and their parts' TODO lines doom them", "[grader]") {
  const CaseGroups g = case_groups({make_case("p6_m3", 6, "CBspheres.dae", {"-m", "3"}),
                                    make_case("p7_dragon", 7, "CBdragon_microfacet_au_0.5.dae"),
                                    make_case("p8_bunny", 8, "bunny_microfacet_envmap.dae", {"-e", "sky_sun.exr"}),
                                    make_case("p9_near", 9, "CBspheres_dof.dae", {"-b", "0.2", "-d", "4.1"}),
                                    make_case("p9_pinhole", 9, "CBspheres_dof.dae", {"-b", "0"})});
  const auto has = [&](const std::string& c, const std::string& group) {
    const std::vector<std::string>& v = g.at(c);
    return std::find(v.begin(), v.end(), group) != v.end();
  };
  CHECK(has("p6_m3", "mirror_glass"));
  CHECK(has("p6_m3", "part6"));
  CHECK_FALSE(has("p7_dragon", "mirror_glass"));
  CHECK(has("p7_dragon", "microfacet"));
  CHECK(has("p7_dragon", "mesh"));
  CHECK(has("p8_bunny", "environment"));
  CHECK(has("p8_bunny", "microfacet"));
  CHECK(has("p9_near", "depth_of_field"));
  CHECK_FALSE(has("p9_pinhole", "depth_of_field"));
  CHECK(todo_part("TODO: implement Part 8: sample_environment (stages/part8_environment_light/x.cpp)") == 8);
  CHECK(todo_part("TODO: implement Part 9: generate_ray_for_thin_lens") == 9);
  CHECK(todo_dooms(7, 8));
  CHECK_FALSE(todo_dooms(8, 7));
  CHECK_FALSE(todo_dooms(2, 9));  // part 2's stand-in finds the right hits
}

TEST_CASE("The noise bound grows per bounce only where a case keeps paths of exactly -m bounces", "[grader]") {
  const Rules rules;
  CHECK(rules.noise_bound_for(make_case("p3", 3, "CBspheres_lambertian.dae", {"-l", "4"})) == Approx(4.0));
  CHECK(rules.noise_bound_for(make_case("p4", 4, "CBspheres_lambertian.dae", {"-m", "5"})) == Approx(4.0));
  CHECK(rules.noise_bound_for(make_case("p4o", 4, "CBspheres_lambertian.dae", {"-m", "2", "-o", "0"})) == Approx(6.0));
  CHECK(rules.noise_bound_for(make_case("p4o5", 4, "CBspheres_lambertian.dae", {"-m", "5", "-o", "0"})) ==
        Approx(4.0 * 1.5 * 1.5 * 1.5 * 1.5));
  CHECK(rules.noise_bound_for(make_case("p4o1", 4, "CBspheres_lambertian.dae", {"-m", "5", "-o", "1"})) == Approx(4.0));
}

TEST_CASE("Signature: the grid says where in the picture the image moved", "[grader]") {
  // 90 x 60, every pixel 1; the candidate twice as bright in the upper-left
  // ninth (rows are stored from the bottom).
  ImageBuffer ref(90, 60), cand(90, 60);
  for (int y = 0; y < 60; ++y)
    for (int x = 0; x < 90; ++x) {
      ref.at(x, y) = pt::Color(1, 1, 1);
      cand.at(x, y) = x < 30 && y >= 40 ? pt::Color(2, 2, 2) : pt::Color(1, 1, 1);
    }
  const Signature s = image_signature(cand, ref, ImageScore{});
  REQUIRE(s.count(grid_key(0, 0)) == 1);
  CHECK(s.at(grid_key(0, 0)) == Approx(2.0));
  CHECK(s.at(grid_key(2, 0)) == Approx(1.0));  // lower-left
  CHECK(s.at(grid_key(0, 2)) == Approx(1.0));  // upper-right
  CHECK(s.at("mean_ratio") == Approx(10.0 / 9.0));
}

TEST_CASE("Hints: of two bugs alike but for where the image moved, the one that moved it where the build did is nearer",
          "[grader]") {
  const auto moved = [](int row, int column) {
    CaseSignature c = failing(1.2);
    for (int r = 0; r < kGridSide; ++r)
      for (int k = 0; k < kGridSide; ++k) c.figures[grid_key(r, k)] = r == row && k == column ? 2.8 : 1.0;
    return c;
  };
  Catalogue cat;
  cat.bugs = {bug("bright_ceiling", 3, "f_ceiling", "ceiling", {{"p3_spheres_light", moved(0, 1)}}),
              bug("bright_floor", 3, "f_floor", "floor", {{"p3_spheres_light", moved(2, 1)}})};
  const CaseGroups groups = case_groups(kCases);
  const BuildSignature build = {{"p3_spheres_light", moved(2, 1)}};
  CHECK(signature_distance(build, cat.bugs[1].cases, groups) <
        signature_distance(build, cat.bugs[0].cases, groups));
  const std::vector<Hint> hints = likely_bugs(build, cat, groups);
  REQUIRE(!hints.empty());
  CHECK(hints[0].bug->name == "bright_floor");
}
