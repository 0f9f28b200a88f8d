// The report's likely causes (hints.h) on small made-up catalogues: a kit's
// solved parts, the direction words against the build's own image ratio,
// the cases each hint explains, and the measurement with whole functions
// left out.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "tests/grader/make_case.h"
#include "grader/src/hints.h"

using namespace grader;
namespace fs = std::filesystem;

namespace {

using grader::test::make_case;

const std::vector<Case> kCases = {make_case("p4_m2", 4, "CBspheres_lambertian.dae", {"-m", "2"}),
                                  make_case("p6_m3", 6, "CBspheres.dae", {"-m", "3"}),
                                  make_case("p6_m5", 6, "CBspheres.dae", {"-m", "5"}),
                                  make_case("p7_dragon", 7, "CBdragon_microfacet_au.dae"),
                                  make_case("p7_bunny", 7, "CBbunny_microfacet_cu.dae")};

CaseSignature failing(double ratio) {
  CaseSignature c;
  c.failed = true;
  c.figures = {{"mean_ratio", ratio}, {"failed_image", 1}};
  return c;
}

KnownBug bug(const std::string& name, int part, const std::string& function, const std::string& file,
             const std::string& hint, BuildSignature cases) {
  KnownBug b;
  b.name = name;
  b.part = part;
  b.function = function;
  b.file = file;
  b.readme = "stages/README.md#Section";
  b.hint = hint;
  b.cases = std::move(cases);
  return b;
}

// A temporary tree: <root>/grader/known_bugs.json and, when given, <root>/solved_parts.txt.
struct Tree {
  fs::path root;
  explicit Tree(const std::string& solved) {
    root = fs::temp_directory_path() / ("pt_hints_tree_" + std::to_string(::getpid()) + "_" +
                                        std::to_string(std::hash<std::string>()(solved)));
    fs::remove_all(root);
    fs::create_directories(root / "grader");
    std::ofstream(root / "grader" / "known_bugs.json")
        << R"({"commit": "x", "date": "d", "bugs": [{"name": "a", "part": 6, "function": "refract", "file": )"
           R"("stages/part6_mirror_glass/specular.cpp", "readme": "r", "hint": "h", "cases": {"p6_m3": )"
           R"({"failed": true, "signature": {"mean_ratio": 0.5}}}}]})";
    if (!solved.empty()) std::ofstream(root / "solved_parts.txt") << solved;
  }
  ~Tree() { fs::remove_all(root); }
  std::string catalogue() const { return (root / "grader" / "known_bugs.json").string(); }
};

}  // namespace

// The 3-2 kit gives parts 1-5 solved: part 4's at_least_one_bounce_radiance
// is written for the student, and a hint must not send them there.
TEST_CASE("Hints: a kit's solved parts are never named, nor their functions", "[grader]") {
  Catalogue cat;
  const BuildSignature glass_dark = {{"p6_m3", failing(0.8)}, {"p6_m5", failing(0.8)}};
  cat.bugs = {bug("delta_dark", 4, "at_least_one_bounce_radiance", "stages/part4_global_illumination/gi.cpp",
                  "the mirror is dark", glass_dark),
              // a bug listed under a later part, in a function of part 4's stage
              bug("delta_dark_too", 6, "at_least_one_bounce_radiance", "stages/part4_global_illumination/gi.cpp",
                  "the glass is dark", glass_dark),
              bug("glass_pdf", 6, "glass_sample_f", "stages/part6_mirror_glass/specular.cpp", "the glass is dark",
                  {{"p6_m3", failing(0.7)}})};
  const CaseGroups groups = case_groups(kCases);
  // Every part the students' (the 3-1 kit, the source tree): the nearest is part 4's.
  std::vector<Hint> hints = likely_bugs(glass_dark, cat, groups);
  REQUIRE(!hints.empty());
  CHECK(hints[0].bug->function == "at_least_one_bounce_radiance");
  cat.solved_parts = {1, 2, 3, 4, 5};
  hints = likely_bugs(glass_dark, cat, groups);
  REQUIRE(!hints.empty());
  for (const Hint& h : hints) {
    CHECK(h.bug->function != "at_least_one_bounce_radiance");
    CHECK(h.bug->part > 5);
  }
  CHECK(hints[0].bug->name == "glass_pdf");
  // One case's hints (grader compare, the viewer) follow the same rule.
  for (const Hint& h : likely_bugs_for_case("p6_m3", failing(0.8), cat, groups))
    CHECK(h.bug->function != "at_least_one_bounce_radiance");
}

TEST_CASE("solved_parts.txt holds comments, then one part a line, and is read beside the catalogue (its tree root)", "[grader]") {
  {
    const Tree t("# Parts this kit gives solved\n# one a line\n1\n2\n3\n4\n5\n");
    CHECK(solved_parts_path(t.catalogue()) == (t.root / "solved_parts.txt").string());
    CHECK(read_catalogue(t.catalogue()).solved_parts == std::set<int>{1, 2, 3, 4, 5});
  }
  {
    const Tree t("# The 3-1 kit gives no part solved\n");
    CHECK(read_catalogue(t.catalogue()).solved_parts.empty());
  }
  {
    const Tree t("");  // the source tree has no such file
    CHECK(read_catalogue(t.catalogue()).solved_parts.empty());
  }
  {
    const Tree t("# comment\n1\nfour\n");
    CHECK_THROWS_WITH(read_catalogue(t.catalogue()),
                      Catch::Contains("solved_parts.txt:3: 'four' is not a part number"));
  }
}

// The textbook Fresnel mutant's build was darker (x0.99) and read "too
// bright toward its silhouettes": the words must follow the build's figure.
TEST_CASE("Hints: 'too bright' and 'too dark' agree with the build's own image ratio", "[grader]") {
  Catalogue cat;
  cat.bugs = {bug("no_G", 7, "microfacet_f", "stages/part7_microfacet/microfacet.cpp",
                  "metal is too bright toward its silhouettes (image {ratio}), and brighter the rougher it is",
                  {{"p7_dragon", failing(1.2)}, {"p7_bunny", failing(1.1)}}),
              bug("no_four", 7, "microfacet_F", "stages/part7_microfacet/microfacet.cpp",
                  "metal is too dark (image {ratio})", {{"p7_dragon", failing(0.3)}})};
  const CaseGroups groups = case_groups(kCases);
  const BuildSignature darker = {{"p7_dragon", failing(0.99)}, {"p7_bunny", failing(0.99)}};
  const std::vector<Hint> hints = likely_bugs(darker, cat, groups);
  REQUIRE(!hints.empty());
  for (const Hint& h : hints) {
    CHECK_THAT(h.words, !Catch::Contains("too bright") && !Catch::Contains("brighter"));
    if (h.bug->name == "no_G")
      CHECK(h.words == "metal is too dark toward its silhouettes (image x0.99), and darker the rougher it is");
  }
  // Barely darker: the figure shows which way (x0.9997, not x1).
  for (const Hint& h : likely_bugs({{"p7_dragon", failing(0.9997)}, {"p7_bunny", failing(0.9997)}}, cat, groups))
    if (h.bug->name == "no_G") CHECK(h.words == "metal is too dark toward its silhouettes (image x0.9997), and darker the rougher it is");
  // A brighter build keeps the bright words, and a dark bug's words turn.
  const BuildSignature brighter = {{"p7_dragon", failing(1.3)}, {"p7_bunny", failing(1.3)}};
  for (const Hint& h : likely_bugs(brighter, cat, groups)) {
    CHECK_THAT(h.words, !Catch::Contains("too dark"));
    if (h.bug->name == "no_four") CHECK(h.words == "metal is too bright (image x1.3)");
  }
}

TEST_CASE("Hints: each names the failing cases it explains, in the report's lines", "[grader]") {
  Catalogue cat;
  cat.bugs = {bug("glass", 6, "glass_sample_f", "stages/part6_mirror_glass/specular.cpp", "the glass is dark",
                  {{"p6_m3", failing(0.7)}, {"p6_m5", failing(0.7)}}),
              bug("mirror", 6, "mirror_sample_f", "stages/part6_mirror_glass/specular.cpp", "the mirror is dark",
                  {{"p7_dragon", failing(0.7)}, {"p6_m3", failing(0.7)}})};
  const CaseGroups groups = case_groups(kCases);
  const BuildSignature build = {{"p6_m3", failing(0.7)}, {"p6_m5", failing(0.7)}, {"p7_dragon", failing(0.7)},
                                {"p4_m2", CaseSignature{}}};
  const std::vector<Hint> hints = likely_bugs(build, cat, groups);
  REQUIRE(hints.size() == 2);
  for (const Hint& h : hints) {
    if (h.bug->name == "glass") {
      CHECK(h.cases == std::vector<std::string>{"p6_m3", "p6_m5"});
      CHECK_THAT(h.text, Catch::EndsWith("; explains p6_m3, p6_m5 (2 of 3 failing cases))"));
    } else {
      CHECK(h.cases == std::vector<std::string>{"p6_m3", "p7_dragon"});
      CHECK_THAT(h.text, Catch::Contains("explains p6_m3, p7_dragon (2 of 3 failing cases)"));
    }
  }
  for (const std::string& line : hint_lines(hints)) CHECK_THAT(line, Catch::Contains("explains p6_m3"));
}

// With every bug of its function left out, a bug's function cannot be
// named: the measurement says so (0 %) rather than borrowing a sibling.
TEST_CASE("Hints measured with whole functions left out: no function is named from its own bugs", "[grader]") {
  Catalogue cat;
  cat.bugs = {bug("glass_a", 6, "glass_sample_f", "stages/part6_mirror_glass/specular.cpp", "a",
                  {{"p6_m3", failing(0.7)}, {"p6_m5", failing(0.7)}}),
              bug("glass_b", 6, "glass_sample_f", "stages/part6_mirror_glass/specular.cpp", "b",
                  {{"p6_m3", failing(0.72)}, {"p6_m5", failing(0.7)}}),
              bug("refract_a", 6, "refract", "stages/part6_mirror_glass/specular.cpp", "c",
                  {{"p6_m3", failing(0.5)}, {"p6_m5", failing(0.6)}})};
  const CaseGroups groups = case_groups(kCases);
  HintRates by_bug, by_function;
  const std::string bug_table = held_out_table(cat, groups, HoldOut::Bug, &by_bug);
  const std::string function_table = held_out_table(cat, groups, HoldOut::Function, &by_function);
  CHECK(by_bug.bugs == 3);
  CHECK(by_bug.function_first == Approx(2.0 / 3.0));  // the glass bugs find each other
  CHECK_THAT(bug_table, Catch::Contains("| glass_a | 6 | glass_sample_f | glass_sample_f"));
  CHECK(by_function.function_top3 == 0.0);
  CHECK(by_function.part_top3 == 1.0);  // refract and glass_sample_f are both part 6's
  CHECK_THAT(function_table, Catch::Contains("| glass_a | 6 | glass_sample_f | refract"));
  CHECK_THAT(function_table, Catch::Contains("Project 3-2 (parts 6-9): right function first 0 of 3"));
}

TEST_CASE("Hints of a graded folder: a folder that is not one is named", "[grader]") {
  CHECK_THROWS_WITH(hint_lines_for_folder("/nonexistent/graded", Catalogue{}, CaseGroups{}),
                    Catch::Contains("/nonexistent/graded: not a grader output folder"));
}

// Of two bugs about as near, the one of the earliest failing case's part
// comes first: a bug of part 6 most often fails part 6's cases first.
TEST_CASE("Hints: of two bugs about as near, the earliest failing part's ranks first, within the same limits", "[grader]") {
  Catalogue cat;
  cat.bugs = {bug("loop_far", 4, "at_least_one_bounce_radiance", "stages/part4_global_illumination/gi.cpp", "a",
                  {{"p6_m3", failing(0.70)}, {"p6_m5", failing(0.70)}}),
              bug("glass_near", 6, "glass_sample_f", "stages/part6_mirror_glass/specular.cpp", "b",
                  {{"p6_m3", failing(0.66)}, {"p6_m5", failing(0.66)}})};
  const CaseGroups groups = case_groups(kCases);
  const BuildSignature build = {{"p6_m3", failing(0.72)}, {"p6_m5", failing(0.72)}};
  const double d_loop = signature_distance(build, cat.bugs[0].cases, groups);
  const double d_glass = signature_distance(build, cat.bugs[1].cases, groups);
  REQUIRE(d_loop < d_glass);
  REQUIRE(d_glass < d_loop + kOwnPartBonus);
  const std::vector<Hint> hints = likely_bugs(build, cat, groups);
  REQUIRE(hints.size() == 2);
  CHECK(hints[0].bug->name == "glass_near");
  CHECK(hints[0].distance == Approx(d_glass));  // the distance shown is the bug's own
  // Far behind (beyond the bonus), the nearer bug stays first.
  cat.bugs[1].cases = {{"p6_m3", failing(0.3)}, {"p6_m5", failing(0.3)}};
  REQUIRE(signature_distance(build, cat.bugs[1].cases, groups) > d_loop + kOwnPartBonus);
  CHECK(likely_bugs(build, cat, groups).front().bug->name == "loop_far");
}
