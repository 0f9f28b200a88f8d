// The pathtracer command line, end to end: course flags, help, bad input,
// outputs, console lines.
#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "common/image_io.h"
#include "tests/support.h"

using namespace pt;
using test::run_pathtracer;

namespace {

const char* const kTinyScene = test::kTinyTriangleScene;

int count_lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

std::string read_bytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// Runs a command that must fail: non-zero exit, exactly one line on stderr
// containing `needle`, and no image written into `dir`.
void expect_clean_failure(const test::TempDir& dir, const std::vector<std::string>& args, const std::string& needle) {
  const auto r = run_pathtracer(args, dir.path());
  INFO("stderr: " << r.err);
  CHECK(r.exit_code != 0);
  CHECK(r.exit_code < 128);  // not a crash
  CHECK(count_lines(r.err) == 1);
  CHECK(r.err.rfind("pathtracer: error: ", 0) == 0);
  CHECK(r.err.find(needle) != std::string::npos);
  for (const std::string& f : test::list_dir(dir.path())) {
    INFO("left behind: " << f);
    CHECK(f.find(".png") == std::string::npos);
    CHECK(f.find(".tmp.") == std::string::npos);
  }
}

}  // namespace

TEST_CASE("help (-h) prints usage and exits 0", "[cli]") {
  const auto r = run_pathtracer({"-h"});
  CHECK(r.exit_code == 0);
  for (const char* flag : {"-s", "-l", "-t", "-m", "-o", "-e", "-b", "-d", "-f", "-r", "-c", "-a", "-H", "-p",
                           "--part", "--seed"})
    CHECK(r.out.find(std::string(flag) + " ") != std::string::npos);
}

namespace {

// The flags `pathtracer -h` lists: each group of names ("-h,--help") with
// its default ("=1"), or "" when it shows none.
std::vector<std::pair<std::vector<std::string>, std::string>> help_flags(const std::string& help) {
  std::vector<std::pair<std::vector<std::string>, std::string>> flags;
  std::istringstream in(help);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("  -", 0) != 0) continue;
    const std::string head = line.substr(2, line.find("  ", 2) == std::string::npos ? std::string::npos
                                                                                    : line.find("  ", 2) - 2);
    std::vector<std::string> names;
    std::stringstream group(head.substr(0, head.find(' ')));
    for (std::string name; std::getline(group, name, ',');) names.push_back(name);
    const size_t eq = head.rfind('=');
    flags.emplace_back(names, eq == std::string::npos ? "" : head.substr(eq + 1));
  }
  return flags;
}

// The rows of a Markdown file's "| flag | meaning | default |" table: the
// flags a row names (the first word of each backticked item of its first
// cell) and its default cell.
std::vector<std::pair<std::vector<std::string>, std::string>> readme_flags(const std::string& text) {
  std::vector<std::pair<std::vector<std::string>, std::string>> rows;
  std::istringstream in(text);
  bool inside = false;
  for (std::string line; std::getline(in, line);) {
    if (!inside) {
      inside = line.rfind("| flag | meaning | default |", 0) == 0;
      continue;
    }
    if (line.rfind("|", 0) != 0) break;
    if (line.rfind("|---", 0) == 0) continue;
    std::vector<std::string> cells;
    std::stringstream row(line.substr(1));
    for (std::string cell; std::getline(row, cell, '|');) cells.push_back(cell);
    REQUIRE(cells.size() >= 3);
    std::vector<std::string> names;
    static const std::regex item("`(-[-A-Za-z]+)[^`]*`");
    for (std::sregex_iterator m(cells[0].begin(), cells[0].end(), item), end; m != end; ++m)
      names.push_back((*m)[1]);
    std::string def = cells[2];
    def.erase(0, def.find_first_not_of(' '));
    def.erase(def.find_last_not_of(' ') + 1);
    rows.emplace_back(names, def);
  }
  return rows;
}

std::string repository_root() {
  const std::string scenes = PT_PROJECT_SCENES;
  return scenes.substr(0, scenes.rfind('/'));
}

}  // namespace

// The README's flag table (and the students' README's, in the reference
// tree) is kept by hand: it must name exactly the flags of -h, with the
// defaults -h shows.
TEST_CASE("the README flag tables list every flag of -h and nothing else, with its defaults", "[cli]") {
  const auto r = run_pathtracer({"-h"});
  REQUIRE(r.exit_code == 0);
  const auto help = help_flags(r.out);
  REQUIRE(help.size() >= 20);
  std::vector<std::string> readmes = {repository_root() + "/README.md"};
  const std::string students = repository_root() + "/instructors/starter_kit/overlay/README.md";
  if (std::filesystem::exists(students)) readmes.push_back(students);
  for (const std::string& readme : readmes) {
    INFO(readme);
    const auto rows = readme_flags(read_bytes(readme));
    REQUIRE(!rows.empty());
    std::map<std::string, std::string> readme_default;  // flag -> its default in the table
    for (const auto& [names, def] : rows) {
      std::vector<std::string> defaults;
      std::stringstream split(def);
      for (std::string d; std::getline(split, d, ',');) defaults.push_back(d.substr(d.find_first_not_of(' ')));
      for (size_t i = 0; i < names.size(); ++i) {
        INFO("the table lists " << names[i] << " twice");
        CHECK(readme_default.count(names[i]) == 0);
        readme_default[names[i]] = defaults.size() == names.size() ? defaults[i] : def;
      }
    }
    std::set<std::string> in_help;
    for (const auto& [names, def] : help) {
      int listed = 0;
      for (const std::string& n : names) {
        in_help.insert(n);
        if (!readme_default.count(n)) continue;
        ++listed;
        if (!def.empty()) {
          INFO("default of " << n);
          CHECK(readme_default[n] == def);
        }
      }
      INFO("-h has " << names[0] << ", the table does not");
      CHECK(listed == 1);
    }
    for (const auto& [name, def] : readme_default) {
      INFO("the table has " << name << ", -h does not");
      CHECK(in_help.count(name) == 1);
    }
  }
}

// docs/differences.md lists the flags the course's command line does not
// have; -h decides which those are.
TEST_CASE("docs/differences.md names every flag the course does not have", "[cli]") {
  const auto r = run_pathtracer({"-h"});
  REQUIRE(r.exit_code == 0);
  const std::set<std::string> course = {"-s", "-l", "-t", "-m", "-o", "-e", "-b", "-d", "-f",
                                        "-r", "-c", "-a", "-H", "-p", "-h", "--help"};
  const std::string text = read_bytes(repository_root() + "/docs/differences.md");
  const size_t row = text.find("| new flags: ");
  REQUIRE(row != std::string::npos);
  const std::string line = text.substr(row, text.find('\n', row) - row);
  for (const auto& [names, def] : help_flags(r.out))
    for (const std::string& n : names) {
      if (course.count(n)) continue;
      INFO(n << " is not in the new-flags row of docs/differences.md: " << line);
      CHECK(line.find("`" + n) != std::string::npos);
    }
}

TEST_CASE("bad flag values fail with one clear line and write nothing", "[cli]") {
  test::TempDir dir;
  test::write_text(dir.file("tiny.dae"), kTinyScene);
  const std::string scene = dir.file("tiny.dae");
  expect_clean_failure(dir, {"-s", "0", scene}, "-s");
  expect_clean_failure(dir, {"-r", "-5", "3", scene}, "-r");
  expect_clean_failure(dir, {"-r", "64", scene}, "-r");
  expect_clean_failure(dir, {"-t", "0", scene}, "-t");
  expect_clean_failure(dir, {"-a", "0", "x", scene}, "-a");
  expect_clean_failure(dir, {"-a", "8", "-0.5", scene}, "-a");
  expect_clean_failure(dir, {"-l", "0", scene}, "-l");
  expect_clean_failure(dir, {"-m", "-1", scene}, "-m");
  expect_clean_failure(dir, {"-b", "-1", scene}, "-b");
  expect_clean_failure(dir, {"-s", "many", scene}, "-s");
  expect_clean_failure(dir, {"-r", "64", "48", "-p", "60", "0", "8", "8", scene}, "-p");
  expect_clean_failure(dir, {"--part", "10", scene}, "--part");
  expect_clean_failure(dir, {"--part", "0", scene}, "--part");
  expect_clean_failure(dir, {"--bogus", scene}, "bogus");
  expect_clean_failure(dir, {}, "scene");
  expect_clean_failure(dir, {"-e", "sky.exr", scene}, "sky.exr");
  expect_clean_failure(dir, {"--env-probability", "p.png", scene}, "--env-probability");
  expect_clean_failure(dir, {"--env-probability", "", scene}, "--env-probability");
  expect_clean_failure(dir, {"--part", "2", "-e", test::project_scene("sky_sun.exr"), "--env-probability", "p.png", scene},
                       "--env-probability");
}

// --env-probability: the map's size, written with the render's other
// outputs; uniform before part 8 (a texel's share of the sphere: darkest at
// the poles, the same along a row), part 8's distributions from it on (the
// sun brightest).
TEST_CASE("every part renders from the command line", "[cli]") {
  test::TempDir dir;
  test::write_text(dir.file("tiny.dae"), kTinyScene);
  for (const char* part : {"1", "2", "3", "4", "5", "6", "7", "8", "9"}) {
    const auto r = run_pathtracer({"--part", part, "-s", "4", "-r", "16", "12", "-f", "o.png", "tiny.dae"}, dir.path());
    INFO("part " << part << ": " << r.err);
    CHECK(r.exit_code == 0);
    CHECK(test::file_exists(dir.file("o.png")));
  }
}

TEST_CASE("bad scene files fail with one line naming the file", "[cli]") {
  test::TempDir dir;
  expect_clean_failure(dir, {dir.file("nope.dae")}, "nope.dae");
  test::write_text(dir.file("garbage.dae"), "this is not xml <<<");
  expect_clean_failure(dir, {dir.file("garbage.dae")}, "garbage.dae");
  test::write_text(dir.file("html.dae"), "<html><body/></html>");
  expect_clean_failure(dir, {dir.file("html.dae")}, "html.dae");
  test::write_text(dir.file("tiny.dae"), kTinyScene);
  expect_clean_failure(dir, {"-c", dir.file("nocam.txt"), dir.file("tiny.dae")}, "nocam.txt");
  expect_clean_failure(dir, {"-f", dir.file("no/such/dir/x.png"), dir.file("tiny.dae")}, "no/such/dir");
}

TEST_CASE("a render writes the PNG, the rate PNG and the PFM, and prints the course's lines", "[cli]") {
  test::TempDir dir;
  test::write_text(dir.file("tiny.dae"), kTinyScene);
  const auto r = run_pathtracer({"--part", "2", "-t", "2", "-s", "2", "-r", "32", "24", "-f", "out.png", "--pfm",
                                 "out.pfm", "--stats-json", "out.json", dir.file("tiny.dae")},
                                dir.path());
  INFO(r.out << r.err);
  REQUIRE(r.exit_code == 0);
  for (const char* line : {"[PathTracer] Collecting primitives... Done!", "[PathTracer] Rendering... 100%!",
                           "[PathTracer] Average speed", "intersection tests per ray.",
                           "[PathTracer] Saving to file: out.png... Done!", "[PathTracer] Job completed."})
    CHECK(r.out.find(line) != std::string::npos);
  // Part 2 has a BVH: the course's lines for it, exact counts.
  CHECK(r.out.find("[PathTracer] Building BVH from 1 primitives... Done!") != std::string::npos);
  CHECK(r.out.find("[PathTracer] BVH traced 1536 rays.") != std::string::npos);  // 32 * 24 * 2
  test::Png png, rate;
  REQUIRE(test::read_png(dir.file("out.png"), &png));
  CHECK(png.width == 32);
  CHECK(png.height == 24);
  REQUIRE(test::read_png(dir.file("out_rate.png"), &rate));
  CHECK(rate.width == 32);
  CHECK(rate.height == 24);
  CHECK((rate.rgb[0] == 255 && rate.rgb[1] == 0 && rate.rgb[2] == 0));  // every pixel took all samples
  // The machine-readable figures carry the same exact counts.
  const std::string json = read_bytes(dir.file("out.json"));
  CHECK(json.rfind("{\n  \"scene\": \"", 0) == 0);
  CHECK(json.find("\"part\": 2,") != std::string::npos);
  CHECK(json.find("\"rays\": 1536,") != std::string::npos);
  CHECK(json.find("\"closest_queries\": 1536,") != std::string::npos);
  CHECK(json.find("\"bvh_nodes\": 1,") != std::string::npos);
  CHECK(json.size() > 2);
  CHECK(json.substr(json.size() - 2) == "}\n");
  const ImageBuffer pfm = read_pfm(dir.file("out.pfm"));
  CHECK(pfm.width == 32);
  // The centre pixel sees the triangle head on: normal (0,0,1) -> (0.5,0.5,1).
  CHECK(pfm.at(16, 12).z == Approx(1.0f));
}

TEST_CASE("without -f the image is named after the scene", "[cli]") {
  test::TempDir dir;
  test::write_text(dir.file("tiny.dae"), kTinyScene);
  const auto r = run_pathtracer({"--part", "2", "tiny.dae"}, dir.path());
  REQUIRE(r.exit_code == 0);
  CHECK(test::file_exists(dir.file("tiny_rate.png")));
  // The course's default size, 800x600, and the whole triangle in view:
  // the top-left corner misses, the centre hits.
  test::Png png;
  REQUIRE(test::read_png(dir.file("tiny.png"), &png));
  CHECK(png.width == 800);
  CHECK(png.height == 600);
  CHECK((png.rgb[0] == 0 && png.rgb[1] == 0 && png.rgb[2] == 0));
  CHECK(png.rgb[(300 * 800 + 400) * 3 + 2] == 255);
}

TEST_CASE("threads 1 and 2 (-t) write byte-identical images", "[cli][determinism]") {
  test::TempDir dir;
  test::write_text(dir.file("tiny.dae"), kTinyScene);
  for (const char* t : {"1", "2"}) {
    const auto r = run_pathtracer({"-t", t, "-s", "4", "-r", "40", "30", "-f", std::string("t") + t + ".png",
                                   "--pfm", std::string("t") + t + ".pfm", "tiny.dae"},
                                  dir.path());
    REQUIRE(r.exit_code == 0);
  }
  CHECK(read_bytes(dir.file("t1.pfm")) == read_bytes(dir.file("t2.pfm")));
  CHECK(read_bytes(dir.file("t1.png")) == read_bytes(dir.file("t2.png")));
}

TEST_CASE("every course scene renders at --part 1 to a PNG of the right size", "[cli][course][part1]") {
  test::TempDir dir;
  for (const char* name : {"CBempty.dae", "CBspheres_lambertian.dae", "CBspheres.dae", "CBbunny.dae", "cow.dae",
                           "plane.dae"}) {
    const std::string scene = test::course_scene(name);
    const auto r = run_pathtracer({"--part", "1", "-s", "1", "-t", "2", "-r", "64", "48", "-f", "out.png", scene},
                                  dir.path());
    INFO(name << ": " << r.err);
    REQUIRE(r.exit_code == 0);
    test::Png png, rate;
    REQUIRE(test::read_png(dir.file("out.png"), &png));
    CHECK(png.width == 64);
    CHECK(png.height == 48);
    REQUIRE(test::read_png(dir.file("out_rate.png"), &rate));
    CHECK(rate.width == 64);
    CHECK(rate.height == 48);
    // Something was hit: not every byte is zero.
    bool any = false;
    for (unsigned char b : png.rgb) any |= b != 0;
    CHECK(any);
  }
}

// ---- Hostile command lines -------------------------------------------------

namespace {

// Runs the pathtracer with its address space limited to `limit_bytes`, so
// that a large allocation fails as it would on a smaller machine.
test::RunResult run_with_memory_limit(const std::vector<std::string>& args, const std::string& cwd,
                                      rlim_t limit_bytes) {
  test::TempDir io;
  const std::string out_path = io.file("stdout"), err_path = io.file("stderr");
  std::vector<std::string> argv_s = {PT_PATHTRACER_EXE};
  argv_s.insert(argv_s.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& s : argv_s) argv.push_back(s.data());
  argv.push_back(nullptr);
  test::RunResult r;
  const pid_t pid = fork();
  if (pid == 0) {
    const int out = open(out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err = open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (out < 0 || err < 0 || dup2(out, 1) < 0 || dup2(err, 2) < 0 || chdir(cwd.c_str()) != 0) _exit(126);
    const rlimit lim{limit_bytes, limit_bytes};
    if (setrlimit(RLIMIT_AS, &lim) != 0) _exit(126);
    execv(argv[0], argv.data());
    _exit(127);
  }
  int status = 0;
  if (pid < 0 || waitpid(pid, &status, 0) != pid) return r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  r.out = read_bytes(out_path);
  r.err = read_bytes(err_path);
  return r;
}

}  // namespace

TEST_CASE("a -p cell whose X+DX or Y+DY overflows int is refused, not rendered outside the image", "[cli]") {
  test::TempDir dir;
  test::write_text(dir.file("tiny.dae"), kTinyScene);
  const std::string scene = dir.file("tiny.dae");
  expect_clean_failure(dir, {"-r", "64", "48", "-p", "2147483600", "0", "100", "8", scene}, "-p");
  expect_clean_failure(dir, {"-r", "64", "48", "-p", "0", "2147483600", "8", "100", scene}, "-p");
  expect_clean_failure(dir, {"-r", "64", "48", "-p", "60", "0", "2147483647", "8", scene}, "-p");
  expect_clean_failure(dir, {"-r", "64", "48", "-p", "64", "0", "1", "1", scene}, "-p");
}

TEST_CASE("NaN, infinite and negative numbers, negative seeds and empty paths are refused", "[cli]") {
  test::TempDir dir;
  test::write_text(dir.file("tiny.dae"), kTinyScene);
  const std::string scene = dir.file("tiny.dae");
  for (const char* v : {"nan", "NaN", "-nan", "inf", "-inf", "1e999", "-1"}) {
    expect_clean_failure(dir, {"-b", v, scene}, "-b");
    expect_clean_failure(dir, {"-d", v, scene}, "-d");
  }
  expect_clean_failure(dir, {"-d", "0", scene}, "-d");
  expect_clean_failure(dir, {"-a", "8", "nan", scene}, "-a");
  expect_clean_failure(dir, {"-a", "8", "inf", scene}, "-a");
  for (const char* v : {"-1", "-0x1", "18446744073709551616", "1.5", "seven", ""})
    expect_clean_failure(dir, {"--seed", v, scene}, "--seed");
  for (const char* flag : {"-e", "-f", "-c", "--pfm", "--stats-json"})
    expect_clean_failure(dir, {flag, "", scene}, flag);
  expect_clean_failure(dir, {""}, "scene");
  // The largest seed is still accepted.
  const auto r = run_pathtracer({"--seed", "18446744073709551615", "-r", "4", "3", "-f", "o.png", scene}, dir.path());
  INFO(r.err);
  CHECK(r.exit_code == 0);
}

TEST_CASE("an -r image too large for memory is refused naming -r", "[cli]") {
  test::TempDir dir;
  test::write_text(dir.file("tiny.dae"), kTinyScene);
  const std::string scene = dir.file("tiny.dae");
  expect_clean_failure(dir, {"-r", "16384", "16384", scene}, "-r");
  expect_clean_failure(dir, {"-r", "16384", "4096", scene}, "-r");
}

TEST_CASE("running out of memory while rendering gives one line naming -r, not a bare std::bad_alloc", "[cli]") {
  test::TempDir dir;
  test::write_text(dir.file("tiny.dae"), kTinyScene);
  // 8000 x 4000 is within the pixel limit but needs about 0.5 GB; allow 256 MB.
  const auto r = run_with_memory_limit({"--part", "1", "-r", "8000", "4000", "-f", "o.png", "tiny.dae"}, dir.path(),
                                       rlim_t(256) << 20);
  INFO("stderr: " << r.err);
  CHECK(r.exit_code == 1);
  CHECK(count_lines(r.err) == 1);
  CHECK(r.err.rfind("pathtracer: error: ", 0) == 0);
  CHECK(r.err.find("-r 8000 4000") != std::string::npos);
  CHECK(r.err.find("memory") != std::string::npos);
  CHECK(r.err.find("std::bad_alloc") == std::string::npos);
  CHECK_FALSE(test::file_exists(dir.file("o.png")));
}

TEST_CASE("an output that is an existing folder is found before rendering, and nothing is written", "[cli]") {
  test::TempDir dir;
  test::write_text(dir.file("tiny.dae"), kTinyScene);
  const std::vector<std::string> base = {"-r", "8", "6", "-f", "o.png"};
  struct Case {
    std::string folder;
    std::vector<std::string> extra;
  };
  for (const Case& c : {Case{"o.pfm", {"--pfm", "o.pfm"}}, Case{"o.json", {"--stats-json", "o.json"}},
                        Case{"o_rate.png", {}}}) {
    INFO("folder " << c.folder);
    std::filesystem::create_directory(dir.file(c.folder));
    std::vector<std::string> args = base;
    args.insert(args.end(), c.extra.begin(), c.extra.end());
    args.push_back("tiny.dae");
    const auto r = run_pathtracer(args, dir.path());
    INFO("stderr: " << r.err);
    CHECK(r.exit_code == 1);
    CHECK(count_lines(r.err) == 1);
    CHECK(r.err.rfind("pathtracer: error: " + c.folder + ": ", 0) == 0);
    CHECK(r.out.find("Rendering") == std::string::npos);  // refused before rendering
    for (const std::string& f : test::list_dir(dir.path())) {
      INFO("left behind: " << f);
      CHECK((f == "tiny.dae" || f == c.folder));
    }
    std::filesystem::remove(dir.file(c.folder));
  }
}

TEST_CASE("outputs naming the scene, an input or each other are refused before anything is done", "[cli]") {
  test::TempDir dir;
  test::write_text(dir.file("tiny.dae"), kTinyScene);
  test::write_text(dir.file("cam.txt"), "30 20 1.5 0.01 50\n0 0 5 0 0 0\n0 0 5 1 10\n1 0 0 0 1 0 0 0 1\n800 600 900\n4 0\n");
  test::write_text(dir.file("sky.exr"), "not really an image, but it must not be overwritten");
  const std::string scene = dir.file("tiny.dae");
  const std::string scene_text = read_bytes(scene);
  struct Case {
    std::vector<std::string> args;
    std::string flag;
  };
  const std::vector<Case> cases = {
      {{"-f", "tiny.dae", "tiny.dae"}, "-f"},
      {{"-f", "./tiny.dae", scene}, "-f"},
      {{"-f", dir.path() + "/../" + std::filesystem::path(dir.path()).filename().string() + "/tiny.dae", "tiny.dae"},
       "-f"},
      {{"--pfm", "tiny.dae", "tiny.dae"}, "--pfm"},
      {{"--stats-json", scene, "tiny.dae"}, "--stats-json"},
      {{"-f", "o.png", "--pfm", "o.png", "tiny.dae"}, "--pfm"},
      {{"-f", "o.png", "--stats-json", "o_rate.png", "tiny.dae"}, "--stats-json"},
      {{"--pfm", "x.pfm", "--stats-json", "./x.pfm", "tiny.dae"}, "--stats-json"},
      {{"-c", "cam.txt", "--pfm", "cam.txt", "tiny.dae"}, "--pfm"},
      {{"-c", "cam.txt", "-f", "cam.txt", "tiny.dae"}, "-f"},
      {{"-e", "sky.exr", "--stats-json", "sky.exr", "tiny.dae"}, "--stats-json"},
      {{"-e", "sky.exr", "--env-probability", "sky.exr", "tiny.dae"}, "--env-probability"},
      {{"-e", "sky.exr", "-f", "o.png", "--env-probability", "o_rate.png", "tiny.dae"}, "--env-probability"},
      {{"-f", "tiny.dae_rate.png", "--pfm", "tiny.dae_rate_rate.png", "tiny.dae"}, "--pfm"},
  };
  for (const Case& c : cases) {
    std::vector<std::string> args = {"-r", "8", "6"};
    args.insert(args.end(), c.args.begin(), c.args.end());
    std::string shown;
    for (const auto& a : args) shown += a + " ";
    INFO("pathtracer " << shown);
    const auto r = run_pathtracer(args, dir.path());
    INFO("stderr: " << r.err);
    CHECK(r.exit_code == 2);
    CHECK(count_lines(r.err) == 1);
    CHECK(r.err.rfind("pathtracer: error: " + c.flag + " ", 0) == 0);
    CHECK(r.out.empty());  // refused before loading anything
    CHECK(read_bytes(scene) == scene_text);
    CHECK(read_bytes(dir.file("sky.exr")) == "not really an image, but it must not be overwritten");
    for (const std::string& f : test::list_dir(dir.path())) {
      INFO("left behind: " << f);
      CHECK((f == "tiny.dae" || f == "cam.txt" || f == "sky.exr"));
    }
  }
}
