// The grader against hostile student binaries (instructors/fake_student/fake_student.cpp):
// one that crashes, hangs, prints garbage, writes a truncated PNG, NaNs, the
// wrong size, nothing, fills the disk, leaves a named pipe or a PFM whose
// header lies, forks children that hang, or exits with an error. Each must
// become a failed case with a message naming the problem, and the grader
// must finish, write every report and return its documented exit code
// (0 all passed, 1 some case failed, 2 usage error or no usable reference).
// Also: shards merge into the unsharded result; a missing reference, a
// malformed case list and a missing binary are usage errors.
//
// Every run works in its own temporary folder: a copy of scenes/CBempty.dae
// per case (16 x 12, part 1: deterministic normal shading), references made
// with the real pathtracer (`grader make-references --runs 2`).
//
// GRADER_UNDER_TEST, when set, names another grader binary to test (a build
// with a planted bug, to see these tests fail).
//
// Every timeout here (the cases', the limit on a whole grader run, the wait
// for a killed process to end) is multiplied by PT_TEST_TIMEOUT_SCALE
// (README, "Tests"), given to the grader as --timeout-scale. The limits only
// bound a failing run: a passing one ends as soon as what it checks happens.
#include <sys/stat.h>

#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "common/image_io.h"
#include "tests/grader/grading_sandbox.h"
#include "tests/support.h"

namespace {

namespace fs = std::filesystem;
using namespace pt::test::grading;
using Catch::Matchers::Contains;
using Catch::Matchers::EndsWith;
using Catch::Matchers::StartsWith;
using pt::test::JsonValue;

// The fake student's behaviours and what the grader must say about each.
struct Mode {
  const char* name;
  bool passes;           // the render is correct (the case passes)
  const char* message;   // part of the case's message (failures); {} is the timeout in s
  double timeout;        // the case's timeout (s)
  int part = 1;          // the case's part (from 2 on, costs are checked)
  size_t processes = 0;  // the fake's processes that record themselves (FAKE_STUDENT_PIDS)
};
const Mode kModes[] = {
    {"good", true, "matches the reference", 20},
    {"crash", false, "crashed: killed by signal 11 (Segmentation fault)", 20},
    {"hang", false, "timed out after {} s (killed)", 1, 1, 2},
    {"fork_hang", true, "matches the reference", 20, 1, 3},
    {"garbage", false, "wrote no image (-f render.png)", 20},
    {"truncated_png", false, "unreadable PNG: ", 20},
    {"nan", false, "2 pixels are NaN or infinite (the first at x=3, y=2 from the top)", 20},
    {"wrong_size", false, "the PNG image is 8 x 6, expected 16 x 12", 20},
    {"wrong_size_pfm", false, "the PFM image is 8 x 6, expected 16 x 12", 20},
    {"nothing", false, "wrote no image (-f render.png)", 20},
    {"no_pfm", false, "wrote no floating-point image (--pfm render.pfm)", 20},
    {"disk_fill", false, "wrote a file larger than the 1 MB limit (killed by SIGXFSZ)", 20},
    {"disk_fill_many", false, "wrote 3 MB, more than the 1 MB limit", 20},
    {"fifo", false, "the image (-f render.png) is not a regular file", 20},
    {"fifo_stats", true, "matches the reference", 20},
    {"huge_pfm", false, "PFM data is truncated", 20},
    {"exit3", false, "exited with status 3", 20},
    // Ten times the limit on the whole grader run: only stopping at the
    // TODO line lets the run finish in time.
    {"todo_hang", false, "Part 1 not implemented (TODO: generate_ray)", 10 * kGraderTimeLimit, 1, 1},
    {"todo_part2", true, "matches the reference", 20},
    {"negative_roundoff", true, "matches the reference", 20},
    {"negative", false, "1 pixel has negative radiance below -1e-4 (the first at x=5, y=6 from the top)", 20},
    {"costly", false, "100.0 intersection tests per camera or bounce ray, more than 3x the reference's", 20, 2},
    {"costly_shadow", false, "100.0 intersection tests per shadow ray, more than 3x the reference's", 20, 2},
    {"uncounted", false, "no intersection tests counted", 20, 2},
};

// A mode's message with the case's timeout, under the grader's --timeout-scale
// `s`, in place of {}.
std::string message_of(const Mode& m, double s) {
  std::string text = m.message;
  const size_t at = text.find("{}");
  if (at != std::string::npos) {
    char seconds[32];
    std::snprintf(seconds, sizeof seconds, "%.0f", m.timeout * s);  // as the grader writes it
    text.replace(at, 2, seconds);
  }
  return text;
}

const Mode& mode(const std::string& name) {
  for (const Mode& m : kModes)
    if (name == m.name) return m;
  throw std::runtime_error("no mode " + name);
}

// The case graded in `out` (with --timeout-scale `timeout_scale`) got the
// verdict its mode calls for.
void check_case(const JsonValue& results, const std::string& out, const Mode& m, double timeout_scale) {
  INFO("case " << m.name);
  const std::string message = message_of(m, timeout_scale);
  const JsonValue& t = test_named(results, m.name);
  const std::string& output = t.at("output").string;
  INFO("output: " << output);
  CHECK(t.at("status").string == (m.passes ? "passed" : "failed"));
  CHECK(t.at("score").number == (m.passes ? kPoints : 0));
  CHECK_THAT(output, StartsWith(m.passes ? "passed: " : "failed: "));
  CHECK_THAT(output, Contains(message));
  const JsonValue c = parse_json_file(out + "/cases/" + m.name + "/result.json");
  CHECK(c.at("verdict").string == (m.passes ? "passed" : "failed"));
  CHECK_THAT(c.at("message").string, Contains(message));
}

// Grades the fake student in `fake_mode` into `out` so that the `processes`
// of it that record themselves had all started when the grader stopped it.
// A hang mode's timeout (1 s) is short so that the test is; on a machine too
// busy to start the fake's processes within it, the run shows nothing about
// the grader, and it is made again with the timeouts doubled (at most three
// times more; a grader that stops the fake too early fails every time).
// Returns the run; *used_scale is the --timeout-scale it had.
Run grade_once_started(const Sandbox& sb, const std::string& fake_mode, const std::string& out, size_t processes,
                       double* used_scale) {
  double s = scale();
  for (int attempt = 0;; ++attempt) {
    kill_recorded(sb.pids());
    std::error_code ec;
    fs::remove(sb.pids(), ec);
    fs::remove_all(out, ec);
    Run g = sb.grade(fake_mode, out, {}, s);
    if (read_recorded(sb.pids()).size() >= processes || attempt == 3) {
      *used_scale = s;
      return g;
    }
    WARN("the fake student's processes had not all started when the grader stopped it (a busy machine): "
         "graded again with --timeout-scale " << 2 * s);
    s *= 2;
  }
}
// Grades the fake student in one mode on a case of its own: the run ends by
// itself with exit code 1 (0 for a passing mode), every report is complete
// and the case has the mode's verdict and message. Returns results.json.
JsonValue grade_one_mode(Sandbox& sb, const std::string& name) {
  const Mode& m = mode(name);
  sb.add_case(m.name, m.timeout, m.part);
  sb.make_references();
  const std::string out = sb.path("out");
  double used_scale = 1;
  const Run g = grade_once_started(sb, m.name, out, m.processes, &used_scale);
  check_finished(g, m.passes ? 0 : 1);
  CHECK(g.err == "");  // the grader reported no error of its own
  const JsonValue results = check_reports(out, {m.name});
  check_case(results, out, m, used_scale);
  CHECK(results.at("score").number == (m.passes ? kPoints : 0));
  return results;
}

void check_no_survivors(const std::string& pids_file, size_t expected) {
  const std::vector<Recorded> recorded = read_recorded(pids_file);
  REQUIRE(recorded.size() == expected);  // every process of the fake said it was there
  const int limit = int(std::ceil(kProcessEndLimit * scale()));
  for (const Recorded& r : recorded) {
    INFO("process " << r.pid << " of the fake student outlived the grader run");
    CHECK(ends_within(r, limit));
  }
}

}  // namespace

// ---- One mode at a time ----

TEST_CASE("good: a correct render passes with full marks") {
  Sandbox sb;
  grade_one_mode(sb, "good");
}

TEST_CASE("crash: failed, killed by signal 11") {
  Sandbox sb;
  grade_one_mode(sb, "crash");
}

TEST_CASE("hang: failed at the case timeout, the hung process and its child killed") {
  Sandbox sb;
  grade_one_mode(sb, "hang");
  check_no_survivors(sb.pids(), 2);
}

TEST_CASE("fork_hang: the render passes, and no forked child or grandchild survives the run") {
  Sandbox sb;
  grade_one_mode(sb, "fork_hang");
  check_no_survivors(sb.pids(), 3);
}

TEST_CASE("garbage: binary output is sanitised into valid JSON and escaped HTML") {
  Sandbox sb;
  const JsonValue results = grade_one_mode(sb, "garbage");
  // The student's output reaches the report (sanitised), so the checks
  // below look at text that is really there.
  const std::string& output = test_named(results, "garbage").at("output").string;
  CHECK_THAT(output, Contains("Output of the render:"));
  CHECK_THAT(output, Contains("[stderr]"));
  CHECK_THAT(output, Contains("<script>alert('fake')</script>"));
  size_t unprintable = 0;
  for (unsigned char c : output) unprintable += !(c == '\n' || c == '\t' || (c >= 0x20 && c < 0x7F));
  CHECK(unprintable == 0);
  const std::string html = slurp(sb.path("out") + "/report.html");
  CHECK_THAT(html, Contains("&lt;script&gt;alert('fake')&lt;/script&gt;"));
  CHECK_THAT(html, !Contains("<script>"));
  const std::string txt = slurp(sb.path("out") + "/report.txt");
  CHECK_THAT(txt, !Contains("\x1b"));
}

TEST_CASE("truncated_png: failed, unreadable PNG") {
  Sandbox sb;
  grade_one_mode(sb, "truncated_png");
}

TEST_CASE("nan: failed, the NaN and infinite pixels counted and the first located") {
  Sandbox sb;
  grade_one_mode(sb, "nan");
}

TEST_CASE("wrong_size: failed, the PNG's size against the case's") {
  Sandbox sb;
  grade_one_mode(sb, "wrong_size");
}

TEST_CASE("wrong_size_pfm: failed, the PFM's size against the case's") {
  Sandbox sb;
  grade_one_mode(sb, "wrong_size_pfm");
}

TEST_CASE("nothing: failed, no image") {
  Sandbox sb;
  grade_one_mode(sb, "nothing");
}

TEST_CASE("no_pfm: failed, no floating-point image") {
  Sandbox sb;
  grade_one_mode(sb, "no_pfm");
}

TEST_CASE("disk_fill: failed, killed at the file-size limit") {
  Sandbox sb;
  grade_one_mode(sb, "disk_fill");
  // The limit stopped it: no file in the case's folder is over 1 MB.
  for (const auto& e : fs::recursive_directory_iterator(sb.path("out/cases/disk_fill")))
    if (e.is_regular_file()) CHECK(e.file_size() <= (1u << 20));
}

TEST_CASE("disk_fill_many: failed, the folder's total over the output limit") {
  Sandbox sb;
  grade_one_mode(sb, "disk_fill_many");
}

TEST_CASE("fifo: a named pipe for the image fails the case instead of blocking the grader") {
  Sandbox sb;
  grade_one_mode(sb, "fifo");
}

TEST_CASE("fifo_stats: a named pipe for the statistics is skipped, the render still passes") {
  Sandbox sb;
  grade_one_mode(sb, "fifo_stats");
}

TEST_CASE("huge_pfm: a PFM header claiming 60000 x 60000 pixels fails without a huge allocation") {
  Sandbox sb;
  grade_one_mode(sb, "huge_pfm");
}

TEST_CASE("exit3: failed, the exit status and the student's stderr reported") {
  Sandbox sb;
  const JsonValue results = grade_one_mode(sb, "exit3");
  CHECK_THAT(test_named(results, "exit3").at("output").string, Contains("fake_student: giving up on purpose"));
}


// The case's timeout (1200 s) is ten times the test's limit on the whole
// grader run (120 s; both times the scale): only stopping the render at its
// TODO line lets it finish.
TEST_CASE("todo_hang: stopped at its TODO line, failed as 'Part 1 not implemented', not at the timeout") {
  Sandbox sb;
  grade_one_mode(sb, "todo_hang");
  check_no_survivors(sb.pids(), 1);
}

TEST_CASE("todo_part2: a Part 2 TODO line does not stop or fail a part 1 case") {
  Sandbox sb;
  grade_one_mode(sb, "todo_part2");
}

TEST_CASE("negative_roundoff and negative: -1e-6 is round-off and passes, -0.01 fails") {
  Sandbox a, b;
  grade_one_mode(a, "negative_roundoff");
  grade_one_mode(b, "negative");
}

TEST_CASE("costly, costly_shadow, uncounted: part 2 cases fail on tests per query of either kind, or none counted") {
  for (const char* m : {"costly", "costly_shadow", "uncounted"}) {
    Sandbox sb;
    grade_one_mode(sb, m);
  }
}

// ---- All modes in one run ----

// The function checks (`pathtracer --probe`) run the build once more when
// it loses points; their file is the build's too, and only orders hints.
TEST_CASE("function checks that write garbage, a link, 20 MB or words of their own: the case is judged as rendered, "
          "and the report quotes none of it") {
  Sandbox sb;
  sb.add_case("nan", 20);
  sb.make_references();
  fs::copy_file(std::string(PT_PROJECT_SCENES) + "/../reference_images/probes.json", sb.refs() + "/probes.json");
  for (const std::string fake : {"probe_garbage", "probe_link", "probe_huge", "probe_evil"}) {
    INFO("fake student mode " << fake);
    const std::string out = sb.path("out_" + fake);
    const Run g = sb.grade(fake, out);
    check_finished(g, 1);
    const JsonValue results = check_reports(out, {"nan"});
    check_case(results, out, mode("nan"), scale());
    const std::string txt = slurp(out + "/report.txt"), html = slurp(out + "/report.html"),
                      json = slurp(out + "/results.json");
    for (const std::string& report : {txt, html, json}) {
      CHECK_THAT(report, !Contains("EVIL") && !Contains("<script>alert") && !Contains("1e30") && !Contains("1e+30"));
    }
    if (fake == "probe_evil") {
      // The grader's own words: the status is read as "not ok", never quoted.
      CHECK(g.err == "");
      // As a likely cause, or in a "Function check" line when no likely cause names it.
      CHECK_THAT(txt, Contains("generate_ray answers the grader's function checks differently from the reference's "
                               "(crashed while checked)") ||
                          Contains("Function check: generate_ray (part 1) answers differently from the reference's: "
                                   "crashed while checked"));
      CHECK_THAT(txt, Contains("intersect_sphere answers the grader's function checks differently from the "
                               "reference's (check '") ||
                          Contains("Function check: intersect_sphere (part 1) answers differently from the "
                                   "reference's: check '"));
    } else {
      CHECK_THAT(txt, !Contains("Function check:"));
    }
    if (fake == "probe_link") {
      CHECK_THAT(g.err, Contains("the function checks did not run: wrote no function checks"));
    }
    if (fake == "probe_huge") {
      CHECK_THAT(g.err, Contains("the function checks did not run:"));
      CHECK_THAT(g.err, Contains("SIGXFSZ"));
    }
  }
}

TEST_CASE("grader functions: the reference build agrees on every function, and a build's own words are not quoted") {
  Sandbox sb;
  const std::string refs = std::string(PT_PROJECT_SCENES) + "/../reference_images";
  Run g = run_program({grader_exe(), "functions", "--pathtracer", PT_PATHTRACER_EXE, "--references", refs, "-o",
                       sb.path("ref_functions")},
                      {});
  INFO(g.summary());
  check_finished(g, 0);
  CHECK_THAT(g.out, Contains("part 6  refract"));
  CHECK_THAT(g.out, !Contains("DIFFERS"));
  CHECK_THAT(g.out, Contains(" functions answer the checks as the reference does (parts 1 to 9)"));
  g = run_program({grader_exe(), "functions", "--pathtracer", FAKE_STUDENT_EXE, "--references", refs, "--part", "1",
                   "-o", sb.path("fake_functions")},
                  {{"FAKE_STUDENT_MODE", "probe_evil"}});
  INFO(g.summary());
  check_finished(g, 1);
  CHECK_THAT(g.out, Contains("part 1  generate_ray                     DIFFERS: crashed while checked"));
  CHECK_THAT(g.out, !Contains("EVIL") && !Contains("<script>"));
  // Parts beyond --part are not judged: only part 1's functions are listed.
  CHECK_THAT(g.out, !Contains("part 2 "));
}

TEST_CASE("every mode in one run with -j 2: each case judged on its own, every report complete") {
  Sandbox sb;
  std::vector<std::string> names;
  double expected_total = 0;
  size_t processes = 0;
  for (const Mode& m : kModes) {
    sb.add_case(m.name, m.timeout, m.part);
    names.push_back(m.name);
    expected_total += m.passes ? kPoints : 0;
    processes += m.processes;
  }
  REQUIRE(processes == 2 + 3 + 1);  // hang's two, fork_hang's three, todo_hang's one
  sb.make_references();
  const std::string out = sb.path("out");
  double used_scale = 1;
  const Run g = grade_once_started(sb, "by_scene", out, processes, &used_scale);
  check_finished(g, 1);
  CHECK(g.err == "");
  const JsonValue results = check_reports(out, names);
  for (const Mode& m : kModes) check_case(results, out, m, used_scale);
  CHECK(results.at("score").number == expected_total);
  check_no_survivors(sb.pids(), processes);
}

// ---- Shards ----

TEST_CASE("shards 1/2 and 2/2 merged give the unsharded run's cases, verdicts and total") {
  Sandbox sb;
  const std::vector<std::string> names = {"good", "crash", "nan", "exit3", "nothing"};
  for (const std::string& n : names) sb.add_case(n, 20);
  sb.make_references();
  const std::string all = sb.path("all"), s1 = sb.path("shard1"), s2 = sb.path("shard2"), merged = sb.path("merged");
  check_finished(sb.grade("by_scene", all), 1);
  check_finished(sb.grade("by_scene", s1, {"--shard", "1/2"}), 1);
  check_finished(sb.grade("by_scene", s2, {"--shard", "2/2"}), 1);
  const Run m = run_program({grader_exe(), "merge", "-o", merged, "--cases", sb.cases(), s1, s2}, {});
  check_finished(m, 1);

  const auto verdicts = [](const JsonValue& results) {
    std::map<std::string, std::pair<std::string, double>> v;
    for (const JsonValue& t : results.at("tests").array)
      v[t.at("name").string] = {t.at("status").string, t.at("score").number};
    return v;
  };
  const JsonValue r_all = check_reports(all, names), r_merged = check_reports(merged, names, false);
  const JsonValue r1 = parse_json_file(s1 + "/results.json"), r2 = parse_json_file(s2 + "/results.json");
  const auto v1 = verdicts(r1), v2 = verdicts(r2);
  // The shards split the cases: disjoint, and together all of them.
  CHECK(v1.size() == 3);
  CHECK(v2.size() == 2);
  for (const auto& [name, v] : v1) CHECK(v2.count(name) == 0);
  CHECK(verdicts(r_merged) == verdicts(r_all));
  CHECK(r_merged.at("score").number == r_all.at("score").number);
  CHECK(r_all.at("score").number == kPoints);  // only "good" passes
  CHECK(r1.at("score").number + r2.at("score").number == r_all.at("score").number);
}

// ---- Usage errors: exit code 2 ----

TEST_CASE("a case without a reference: exit 2, the case named, the other cases still graded") {
  Sandbox sb;
  sb.add_case("good", 20);
  sb.add_case("orphan", 20);
  sb.make_references("good");
  const std::string out = sb.path("out");
  const Run g = sb.grade("good", out);
  check_finished(g, 2);
  INFO(g.summary());
  const std::string why = "no reference in " + sb.refs() + "/orphan (make it with: grader make-references --case orphan)";
  CHECK_THAT(g.out, Contains(why));
  const JsonValue results = check_reports(out, {"good", "orphan"});
  CHECK(test_named(results, "good").at("status").string == "passed");
  CHECK(test_named(results, "orphan").at("status").string == "failed");
  CHECK_THAT(test_named(results, "orphan").at("output").string, StartsWith("error: " + why));
  CHECK(parse_json_file(out + "/cases/orphan/result.json").at("verdict").string == "error");

  SECTION("a reference made for another definition of the case is not usable either") {
    pt::test::write_text(sb.cases(), "good 1 image 2 20 good.dae -r 16 12 -s 2\n");
    const Run stale = sb.grade("good", sb.path("out_stale"));
    check_finished(stale, 2);
    CHECK_THAT(stale.out, Contains("was made for another definition of the case"));
  }
}

TEST_CASE("a malformed case list: exit 2 and one line naming file:line, nothing graded") {
  struct Bad {
    const char* line;
    const char* why;
  };
  const Bad bad[] = {
      {"p1 1 image 2 20", "expected: name part kind points timeout scene [options...]"},
      {"p1 1 picture 2 20 good.dae", "unknown kind 'picture' (image, rate, speedup, probability)"},
      {"p1 10 image 2 20 good.dae", "part must be 1..9"},
      {"p1 0 image 2 20 good.dae", "part must be 1..9"},
      {"p1 1 image -2 20 good.dae", "points must be a number >= 0"},
      {"p1 1 image 2 0 good.dae", "timeout must be seconds > 0"},
      {"p1 1 image 2 abc good.dae", "timeout must be seconds > 0"},
      {"good 1 image 2 20 good.dae", "duplicate case name 'good'"},
      {"../escape 1 image 2 20 good.dae", "case name '../escape' must be letters, digits, _ or -"},
      {"p1 1 image 2 20 good.dae -f x.png", "option -f is set by the grader, not the case"},
  };
  for (const Bad& b : bad) {
    Sandbox sb;
    pt::test::write_text(sb.cases(), "# header\ngood 1 image 2 20 good.dae -r 16 12\n" + std::string(b.line) + "\n");
    const std::string out = sb.path("out");
    const Run g = sb.grade("good", out);
    INFO("case line: " << b.line);
    check_finished(g, 2);
    CHECK(g.err == "grader: " + sb.cases() + ":3: " + b.why + "\n");
    CHECK_FALSE(fs::exists(out + "/results.json"));
  }
  SECTION("no case at all, or no file") {
    Sandbox sb;
    pt::test::write_text(sb.cases(), "# only comments\n\n");
    const Run empty = sb.grade("good", sb.path("out"));
    check_finished(empty, 2);
    CHECK(empty.err == "grader: " + sb.cases() + ": no cases\n");
    fs::remove(sb.cases());
    const Run missing = sb.grade("good", sb.path("out"));
    check_finished(missing, 2);
    CHECK(missing.err == "grader: " + sb.cases() + ": cannot open the case list\n");
  }
}

TEST_CASE("a pathtracer that is not an executable file: exit 2 before any case runs") {
  Sandbox sb;
  sb.add_case("good", 20);
  sb.make_references();
  const std::string not_executable = sb.path("not_executable");
  pt::test::write_text(not_executable, "#!/bin/sh\nexit 0\n");
  chmod(not_executable.c_str(), 0644);
  int n = 0;
  for (const std::string& binary : {std::string("/nonexistent/pathtracer"), sb.path("scenes"), not_executable}) {
    INFO("--pathtracer " << binary);
    const std::string out = sb.path("out" + std::to_string(++n));
    const Run g = run_program({grader_exe(), "run", "--pathtracer", binary, "--cases", sb.cases(), "--references",
                               sb.refs(), "--scenes", sb.scenes(), "-o", out},
                              {});
    check_finished(g, 2);
    CHECK(g.err == "grader: " + binary + ": not an executable file\n");
    CHECK(count_lines(g.err) == 1);
    CHECK_FALSE(fs::exists(out + "/results.json"));
  }
}

// ---- grader compare ----

TEST_CASE("compare: --list prints each case's command, a PFM gets a verdict, a PNG an 8-bit comparison") {
  Sandbox sb;
  sb.add_case("good", 20);
  sb.make_references();
  const auto grader = [&](std::vector<std::string> args) {
    std::vector<std::string> argv = {grader_exe(), "compare", "--cases", sb.cases(), "--references", sb.refs(),
                                     "--scenes", sb.scenes(), "-o", sb.path("cmp")};
    argv.insert(argv.end(), args.begin(), args.end());
    return run_program(argv, {});
  };
  const Run list = grader({"--list"});
  check_finished(list, 0);
  CHECK_THAT(list.out, Contains("good ") && Contains("--part 1 -r 16 12 --seed 1 -f good.png --pfm good.pfm"));

  // The case's own command, as --list gives it, with the real pathtracer.
  const std::string png = sb.path("good.png"), pfm = sb.path("good.pfm");
  const pt::test::RunResult r = pt::test::run_pathtracer(
      {"--part", "1", "-r", "16", "12", "--seed", "1", "-f", png, "--pfm", pfm, sb.scenes() + "/good.dae"});
  REQUIRE(r.exit_code == 0);
  const Run same = grader({"good", pfm});
  check_finished(same, 0);
  CHECK_THAT(same.out, Contains("good: matches the reference"));
  CHECK(fs::exists(sb.path("cmp/compare_good.png")));
  CHECK_THAT(slurp(sb.path("cmp/compare_good.html")), StartsWith("<!DOCTYPE html>") && Contains("good.pfm"));

  // 3 % brighter everywhere: a deterministic case differs.
  pt::ImageBuffer img = pt::read_pfm(pfm);
  for (pt::Color& c : img.pixels) c = c * 1.03f;
  const std::string bright = sb.path("bright.pfm");
  pt::write_pfm(bright, img);
  const Run differs = grader({"good", bright});
  check_finished(differs, 1);
  CHECK_THAT(differs.out, Contains("good: differs from the reference"));

  const Run eight_bit = grader({"good", png});
  check_finished(eight_bit, 0);
  CHECK_THAT(eight_bit.out, Contains("compared in 8 bits") && Contains("levels of 255"));

  pt::write_pfm(sb.path("small.pfm"), pt::ImageBuffer(8, 6));
  const Run small = grader({"good", sb.path("small.pfm")});
  check_finished(small, 2);
  CHECK_THAT(small.err, Contains("small.pfm: the image is 8 x 6, case good renders 16 x 12"));
  check_finished(grader({"nosuchcase", pfm}), 2);
  check_finished(grader({"good", sb.path("missing.pfm")}), 2);
}

TEST_CASE("compare: a PFM that differs names the likely cause from the known bugs, one that matches none") {
  // The project's own case list, references and catalogue. Case
  // p3_spheres_light's reference mean times pi is what a diffuse BSDF that
  // forgets to divide the albedo by pi renders (grader/known_bugs.json:
  // albedo_not_over_pi, in the function the catalogue names).
  const fs::path root = fs::path(PT_PROJECT_SCENES).parent_path();
  pt::test::TempDir tmp;
  const auto grader = [&](const std::string& file, const std::string& catalogue) {
    return run_program({grader_exe(), "compare", "--cases", (root / "grader/cases.txt").string(), "--references",
                        (root / "reference_images").string(), "--catalogue", catalogue, "-o", tmp.file("cmp"),
                        "p3_spheres_light", file},
                       {});
  };
  const std::string known_bugs = (root / "grader/known_bugs.json").string();
  std::string function;
  const JsonValue catalogue = parse_json_file(known_bugs);
  for (const JsonValue& b : catalogue.at("bugs").array)
    if (b.at("name").string == "albedo_not_over_pi") function = b.at("function").string;
  REQUIRE(!function.empty());
  const pt::ImageBuffer mean = pt::read_pfm((root / "reference_images/p3_spheres_light/mean.pfm").string());
  pt::ImageBuffer times_pi = mean;
  for (pt::Color& c : times_pi.pixels) c = c * 3.14159265f;
  const std::string pi_pfm = tmp.file("times_pi.pfm"), mean_pfm = tmp.file("mean.pfm");
  pt::write_pfm(pi_pfm, times_pi);
  pt::write_pfm(mean_pfm, mean);

  const Run differs = grader(pi_pfm, known_bugs);
  check_finished(differs, 1);
  INFO(differs.out);
  CHECK_THAT(differs.out, Contains("p3_spheres_light: differs from the reference"));
  const std::string first = "\nLikely cause 1 of ";
  REQUIRE(differs.out.find(first) != std::string::npos);
  const size_t at = differs.out.find(first) + 1;
  const std::string line = differs.out.substr(at, differs.out.find('\n', at) - at);
  CHECK_THAT(line, Contains("every lit image is too bright by about pi (image x3.1)") &&
                       EndsWith("(" + function + " in common/bsdf.h; read stages/part3_direct_lighting/README.md "
                                "(\"Given code\"); explains p3_spheres_light (1 of 1 failing case))"));
  int hints = 0;
  for (size_t p = 0; (p = differs.out.find("\nLikely cause ", p)) != std::string::npos; ++p) ++hints;
  CHECK(hints <= 3);
  CHECK_THAT(slurp(tmp.file("cmp/compare_p3_spheres_light.html")),
             Contains("<p class=\"hint\">Likely cause 1 of ") && Contains("(" + function + " in common/bsdf.h;"));

  const Run same = grader(mean_pfm, known_bugs);
  check_finished(same, 0);
  CHECK_THAT(same.out, Contains("p3_spheres_light: matches the reference"));
  CHECK_THAT(same.out + slurp(tmp.file("cmp/compare_p3_spheres_light.html")), !Contains("Likely cause"));

  // A PNG has no verdict, so no likely cause either.
  const std::string pi_png = tmp.file("times_pi.png");
  pt::write_png(pi_png, times_pi);
  const Run eight_bit = grader(pi_png, known_bugs);
  check_finished(eight_bit, 0);
  CHECK_THAT(eight_bit.out, Contains("compared in 8 bits") && !Contains("Likely cause"));

  // A catalogue whose one bug fails another case: nothing in it is close.
  const std::string other = tmp.file("other_bugs.json");
  pt::test::write_text(other, R"({"commit": "x", "date": "y", "bugs": [{"name": "sphere_root", "part": 1,
    "function": "intersect_sphere", "file": "stages/part1_raytracing/sphere.cpp", "readme": "README.md#Spheres",
    "hint": "spheres inside out", "cases": {"p1_spheres": {"failed": true, "signature": {"mean_ratio": 0.9}}}}]})");
  const Run none = grader(pi_pfm, other);
  check_finished(none, 1);
  CHECK_THAT(none.out, Contains("\nLikely cause: no known bug's signature is close to this one") &&
                           !Contains("Likely cause 1"));
  // Without a catalogue, compare says nothing of causes.
  const Run without = grader(pi_pfm, tmp.file("missing.json"));
  check_finished(without, 1);
  CHECK_THAT(without.out, !Contains("Likely cause"));
}
