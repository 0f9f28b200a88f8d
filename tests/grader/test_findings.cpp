// What a grading run notices across cases (findings.h), on made-up results.
#include <catch2/catch.hpp>

#include "grader/src/findings.h"
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
