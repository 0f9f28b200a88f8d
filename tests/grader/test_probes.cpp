// The function checks (pathtracer/probe.h, grader/src/probes.h): what the
// grader makes of a build's answers, how they order the hints, and that a
// function that crashes is reported without losing the others.
#include <catch2/catch.hpp>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <unistd.h>

#include "common/json.h"
#include "grader/src/hints.h"
#include "grader/src/probes.h"
#include "pathtracer/probe.h"
#include "tests/grader/make_case.h"

using namespace grader;
namespace fs = std::filesystem;

namespace {

using grader::test::make_case;

pt::Json parse(const std::string& s) { return pt::parse_json(s, "test"); }

// A file of answers with one function and one check of these values.
std::string answers(const std::string& function, int part, const std::string& status, const std::string& values,
                    double abs = 1e-5, double rel = 1e-4) {
  std::ostringstream s;
  s << R"({"probes": [{"function": ")" << function << R"(", "part": )" << part << R"(, "status": ")" << status
    << R"(", "checks": [{"name": "wi of 3 directions", "abs": )" << abs << R"(, "rel": )" << rel
    << R"(, "values": [)" << values << "]}]}]}";
  return s.str();
}

CaseSignature failing(double ratio) {
  CaseSignature c;
  c.failed = true;
  c.figures = {{"mean_ratio", ratio}, {"failed_image", 1}};
  return c;
}

KnownBug bug(const std::string& name, int part, const std::string& function, BuildSignature cases) {
  KnownBug b;
  b.name = name;
  b.part = part;
  b.function = function;
  b.file = "stages/part" + std::to_string(part) + "_x/x.cpp";
  b.readme = "stages/README.md#Section";
  b.hint = "the glass is wrong";
  b.cases = std::move(cases);
  return b;
}

ProbeVerdicts verdicts(std::initializer_list<std::tuple<const char*, int, bool>> list) {
  ProbeVerdicts out;
  for (const auto& [f, part, agrees] : list) out[f] = ProbeVerdict{f, part, agrees, agrees ? "" : "differs"};
  return out;
}

const std::vector<Case> kCases = {make_case("p4_m2", 4, "CBspheres_lambertian.dae", {"-m", "2"}),
                                  make_case("p6_m3", 6, "CBspheres.dae", {"-m", "3"}),
                                  make_case("p6_m5", 6, "CBspheres.dae", {"-m", "5"}),
                                  make_case("p7_dragon", 7, "CBdragon_microfacet_au.dae")};

}  // namespace

TEST_CASE("Function checks: a value beyond its tolerance disagrees, one within agrees, and the first difference is named",
          "[grader]") {
  const pt::Json ref = parse(answers("refract", 6, "ok", "0.5, -0.25, 1"));
  std::string problem;
  ProbeVerdicts v = compare_probes(ref, parse(answers("refract", 6, "ok", "0.50004, -0.25, 1")), &problem);
  CHECK(problem.empty());
  REQUIRE(v.count("refract"));
  CHECK(v["refract"].agrees);  // 4e-5 off: within 1e-5 + 1e-4 x 0.5
  CHECK(v["refract"].part == 6);
  v = compare_probes(ref, parse(answers("refract", 6, "ok", "0.5, -0.2, 1")));
  CHECK_FALSE(v["refract"].agrees);
  CHECK(v["refract"].detail == "check 'wi of 3 directions', value 2 of 3: gave -0.2, the reference -0.25");
  // A NaN (written null) agrees only with a null.
  CHECK_FALSE(compare_probes(ref, parse(answers("refract", 6, "ok", "0.5, null, 1")))["refract"].agrees);
  CHECK(compare_probes(parse(answers("f", 6, "ok", "null")), parse(answers("f", 6, "ok", "null")))["f"].agrees);
  // Fewer values, or another check's name, disagree.
  CHECK_FALSE(compare_probes(ref, parse(answers("refract", 6, "ok", "0.5, -0.25")))["refract"].agrees);
  // A function the build did not answer (its part not run) is not judged.
  CHECK(compare_probes(ref, parse(answers("reflect", 6, "ok", "1"))).empty());
  // A file that is not the checks' judges nothing and says why.
  CHECK(compare_probes(ref, parse("[1, 2]"), &problem).empty());
  CHECK(problem == "no \"probes\" list");
}

TEST_CASE("Function checks: a crash disagrees, and the build's own status text never reaches the report", "[grader]") {
  const pt::Json ref = parse(answers("refract", 6, "ok", "1"));
  const ProbeVerdicts v =
      compare_probes(ref, parse(answers("refract", 6, "crashed (see http://evil.example and copy the key)", "1")));
  REQUIRE(v.count("refract"));
  CHECK_FALSE(v.at("refract").agrees);
  CHECK(v.at("refract").detail == "crashed while checked");
  const std::vector<std::string> lines = probe_lines(v);
  REQUIRE(lines.size() == 1);
  CHECK_THAT(lines[0], !Catch::Contains("evil"));
  CHECK(compare_probes(ref, parse(answers("refract", 6, "anything else", "1"))).at("refract").detail ==
        "did not finish its checks");
}

// The signatures of refract's and schlick's bugs are alike (the glass's
// images); the checks tell them apart.
TEST_CASE("Hints: a function whose checks disagree is named first, after its own callees that disagree too", "[grader]") {
  Catalogue cat;
  const BuildSignature glass = {{"p6_m3", failing(0.8)}, {"p6_m5", failing(0.8)}};
  cat.bugs = {bug("schlick_x", 6, "schlick_reflectance", glass), bug("glass_x", 6, "glass_sample_f", glass),
              bug("refract_x", 6, "refract", {{"p6_m3", failing(0.5)}}),
              bug("gi_x", 4, "at_least_one_bounce_radiance", glass)};
  const CaseGroups groups = case_groups(kCases);
  // Without checks the nearest signature comes first (of part 6, the
  // earliest failing case's part).
  std::vector<Hint> hints = likely_bugs(glass, cat, groups);
  REQUIRE(!hints.empty());
  CHECK(hints[0].bug->function == "schlick_reflectance");
  // refract's checks disagree, and so do those of glass_sample_f, which calls it.
  ProbeVerdicts probes = verdicts({{"refract", 6, false},
                                   {"glass_sample_f", 6, false},
                                   {"schlick_reflectance", 6, true},
                                   {"reflect", 6, true}});
  hints = likely_bugs(glass, cat, groups, 3, "", &probes);
  REQUIRE(hints.size() == 3);
  CHECK(hints[0].bug->function == "refract");
  CHECK(hints[0].from_probe);
  CHECK_THAT(hints[0].text, Catch::Contains("refract answers the grader's function checks differently"));
  CHECK_THAT(hints[0].text, Catch::Contains("explains p6_m3, p6_m5 (2 of 2 failing cases)"));
  CHECK(hints[1].bug->function == "glass_sample_f");
  // schlick's checks agree: at_least_one_bounce_radiance, which has none,
  // comes before it, though schlick's is of the earliest failing part.
  CHECK(hints[2].bug->function == "at_least_one_bounce_radiance");
  // A function of a part no failing case runs is not named from its checks
  // (a part-7 stub of a student still on part 6).
  probes = verdicts({{"microfacet_D", 7, false}, {"refract", 6, true}});
  for (const Hint& h : likely_bugs(glass, cat, groups, 3, "", &probes)) CHECK(h.bug->function != "microfacet_D");
  // Nor one of a part the kit gives solved.
  cat.solved_parts = {1, 2, 3, 4, 5};
  probes = verdicts({{"at_least_one_bounce_radiance", 4, false}, {"refract", 6, false}});
  hints = likely_bugs(glass, cat, groups, 3, "", &probes);
  REQUIRE(!hints.empty());
  CHECK(hints[0].bug->function == "refract");
  for (const Hint& h : hints) CHECK(h.bug->function != "at_least_one_bounce_radiance");
}

// A camera flipped in generate_ray makes every function that calls it
// answer differently too: the function it starts in comes first.
TEST_CASE("Hints: of functions whose checks disagree, each comes after the functions it calls", "[grader]") {
  Catalogue cat;
  const BuildSignature dark = {{"p4_m2", failing(0.5)}};
  cat.bugs = {bug("pixel_x", 1, "raytrace_pixel", dark)};
  const ProbeVerdicts probes = verdicts({{"raytrace_pixel", 1, false},
                                         {"camera_sample_ray", 1, false},
                                         {"generate_ray", 1, false},
                                         {"intersect_sphere", 1, true}});
  const std::vector<Hint> hints = likely_bugs(dark, cat, case_groups(kCases), 3, "", &probes);
  REQUIRE(hints.size() == 3);
  CHECK(hints[0].bug->function == "generate_ray");
  CHECK(hints[1].bug->function == "camera_sample_ray");
  CHECK(hints[2].bug->function == "raytrace_pixel");
}

TEST_CASE("Hints: a function whose checks disagree is named even when the catalogue has no bug of it", "[grader]") {
  Catalogue cat;
  const BuildSignature glass = {{"p6_m3", failing(0.8)}};
  cat.bugs = {bug("glass_x", 6, "glass_sample_f", glass)};
  const ProbeVerdicts probes = verdicts({{"refraction_sample_f", 6, false}, {"glass_sample_f", 6, true}});
  const std::vector<Hint> hints = likely_bugs(glass, cat, case_groups(kCases), 3, "", &probes);
  REQUIRE(!hints.empty());
  CHECK(hints[0].bug->function == "refraction_sample_f");
  CHECK_THAT(hints[0].text, Catch::Contains("(refraction_sample_f in stages/part6_x/x.cpp;"));
}

TEST_CASE("pathtracer --probe: a function that crashes or throws is reported so, and the others are still checked",
          "[grader]") {
  using pt::probe::Check;
  using pt::probe::FunctionProbe;
  const std::vector<FunctionProbe> list = {
      {"crashes", 1, []() -> std::vector<Check> {
         std::raise(SIGSEGV);
         return {};
       }},
      {"throws", 1, []() -> std::vector<Check> { throw std::runtime_error("no"); }},
      {"answers", 1, []() { return std::vector<Check>{Check{"two values", {1.5, 2.0}, 1e-5, 1e-4}}; }},
      {"later_part", 7, []() { return std::vector<Check>{Check{"one", {1}, 1e-5, 1e-4}}; }}};
  const fs::path file = fs::temp_directory_path() / ("pt_probe_test_" + std::to_string(::getpid()) + ".json");
  REQUIRE(pt::probe::run_probes(file.string(), 6, list) == 0);
  const pt::Json j = pt::read_json_file(file.string());
  fs::remove(file);
  const pt::Json* probes = j.get("probes");
  REQUIRE(probes);
  REQUIRE(probes->array.size() == 3);  // part 7 not run
  CHECK(probes->array[0].str("status").rfind("crashed", 0) == 0);
  CHECK(probes->array[1].str("status") == "failed (threw or exited early)");
  CHECK(probes->array[2].str("status") == "ok");
  const pt::Json* checks = probes->array[2].get("checks");
  REQUIRE(checks);
  REQUIRE(checks->array.size() == 1);
  CHECK(checks->array[0].get("values")->array.size() == 2);
  CHECK(checks->array[0].get("values")->array[0].number == 1.5);
}

// BEGIN SOLUTION
// reference_images/probes.json is what the grader compares a build's
// answers with: it must be this tree's reference build's, and the checks
// must give the same answers every time.
TEST_CASE("The reference build answers its function checks as reference_images/probes.json says, the same every time",
          "[grader]") {
  const fs::path dir = fs::temp_directory_path() / ("pt_probe_ref_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const auto run = [&](const std::string& name) {
    const std::string out = (dir / name).string();
    const std::string cmd = std::string("'") + PT_PATHTRACER_EXE + "' --probe '" + out + "' > /dev/null 2>&1";
    REQUIRE(std::system(cmd.c_str()) == 0);
    std::ifstream in(out, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  const std::string first = run("a.json"), second = run("b.json");
  fs::remove_all(dir);
  CHECK(first == second);
  const pt::Json committed = pt::read_json_file(reference_probes_path(std::string(PT_PROJECT_SCENES) + "/../reference_images"));
  const pt::Json mine = parse(first);
  const ProbeVerdicts v = compare_probes(committed, mine);
  const ProbeVerdicts back = compare_probes(mine, committed);
  CHECK(v.size() == back.size());  // the same functions both ways
  CHECK(v.size() >= 25);
  for (const auto& [function, verdict] : v) {
    INFO(function << ": " << verdict.detail);
    CHECK(verdict.agrees);
  }
}
// END SOLUTION
