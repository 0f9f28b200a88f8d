// A seeded fuzzer of the pathtracer's command line: random combinations of
// flags with values valid and invalid (NaN, overflowing integers, empty
// paths, outputs naming inputs or each other, folders in the way of
// outputs, ...) against the real executable on tiny scenes at a tiny -r.
// Every run must end with
//   - exit status 0, 1 (an error while working) or 2 (a bad command line),
//     never a signal, and within --timeout seconds (a hang);
//   - on failure: one `pathtracer: error:` line, last on stderr (other
//     lines only `pathtracer: warning:`, or the starter kit's stubs'
//     `TODO: implement`), nothing on stdout for status 2,
//     and no file created or changed anywhere;
//   - on success: no error line, every output there and complete;
//   - never a temporary file left behind, never an input overwritten.
//
//   fuzz_cli [--seed N] [--runs N] [--seconds S] [--timeout S] [--pathtracer EXE]
//
// Exit status 0 when every run kept the contract, 1 otherwise (each broken
// run is printed with its command line), 2 on bad arguments.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support.h"

namespace fs = std::filesystem;

namespace {

struct Random {  // SplitMix64
  uint64_t state;
  explicit Random(uint64_t seed) : state(seed) {}
  uint64_t next() {
    uint64_t z = (state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  size_t below(size_t n) { return n == 0 ? 0 : size_t(next() % n); }
  bool chance(double p) { return double(next() >> 11) * 0x1.0p-53 < p; }
  int in(int lo, int hi) { return lo + int(below(size_t(hi - lo + 1))); }
  template <typename T>
  const T& pick(const std::vector<T>& v) { return v[below(v.size())]; }
};

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// Every file under `dir` (recursively) with its contents; folders end in '/'.
std::map<std::string, std::string> snapshot(const std::string& dir) {
  std::map<std::string, std::string> files;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(dir, ec); it != fs::recursive_directory_iterator(); it.increment(ec)) {
    if (ec) break;
    const std::string rel = fs::relative(it->path(), dir).string();
    if (it->is_directory()) files[rel + "/"] = "";
    else files[rel] = slurp(it->path().string());
  }
  return files;
}

struct Run {
  int status = -1;   // exit status, or 128 + signal
  bool hung = false;
  std::string out, err;
};

// Runs `exe args` in `cwd`; the child is killed by SIGALRM after `timeout` s.
Run run(const std::string& exe, const std::vector<std::string>& args, const std::string& cwd,
        const std::string& io_dir, unsigned timeout) {
  const std::string out_path = io_dir + "/stdout", err_path = io_dir + "/stderr";
  std::vector<std::string> argv_s = {exe};
  argv_s.insert(argv_s.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& s : argv_s) argv.push_back(s.data());
  argv.push_back(nullptr);
  Run r;
  const pid_t pid = fork();
  if (pid == 0) {
    if (!freopen(out_path.c_str(), "w", stdout) || !freopen(err_path.c_str(), "w", stderr) ||
        !freopen("/dev/null", "r", stdin) || chdir(cwd.c_str()) != 0)
      _exit(126);
    signal(SIGALRM, SIG_DFL);
    alarm(timeout);  // survives exec: the default action ends a hung run
    execv(argv[0], argv.data());
    _exit(127);
  }
  int status = 0;
  if (pid < 0 || waitpid(pid, &status, 0) != pid) return r;
  if (WIFEXITED(status)) {
    r.status = WEXITSTATUS(status);
  } else {
    r.status = 128 + WTERMSIG(status);
    r.hung = WTERMSIG(status) == SIGALRM;
  }
  r.out = slurp(out_path);
  r.err = slurp(err_path);
  return r;
}

std::vector<std::string> lines_of(const std::string& s) {
  std::vector<std::string> v;
  std::istringstream in(s);
  for (std::string l; std::getline(in, l);) v.push_back(l);
  return v;
}

// A message reduced to its shape, for counting distinct outcomes.
std::string shape(const std::string& m) {
  std::string out;
  for (size_t i = 0; i < m.size() && out.size() < 70; ++i) {
    const char c = m[i];
    if (std::isdigit(static_cast<unsigned char>(c))) {
      if (out.empty() || out.back() != '#') out += '#';
    } else if (c == '\'') {
      const size_t e = m.find(c, i + 1);
      if (e == std::string::npos) break;
      out += "..";
      i = e;
    } else {
      out += c;
    }
  }
  return out;
}

// ---- The inputs every run may read ----------------------------------------

const char* const kCamera = "49.13 37.85 1.333 0.1 100\n0 0 5 0 0 0\n0 0 5 1 100\n1 0 0 0 1 0 0 0 1\n800 600 875\n4.7 0\n";
const char* const kCameraZero = "49.13 37.85 1.333 0.1 100\n0 0 5 0 0 0\n0 0 5 1 100\n0 0 0 0 0 0 0 0 0\n800 600 875\n4.7 0\n";
const char* const kCameraNan = "49.13 nan 1.333 0.1 100\n0 0 5 0 0 0\n0 0 5 1 100\n1 0 0 0 1 0 0 0 1\n800 600 875\n4.7 0\n";

void write_inputs(const std::string& dir, const std::string& sky) {
  fs::create_directories(dir + "/folder");
  pt::test::write_text(dir + "/tiny.dae", pt::test::kTinyTriangleScene);
  pt::test::write_text(dir + "/ball.dae", slurp(pt::test::project_scene("sphere_ambient.dae")));
  pt::test::write_text(dir + "/garbage.dae", "<COLLADA><asset><up_axis>Y_UP</up_axis></asset><library_geometries>");
  pt::test::write_text(dir + "/empty.dae", "");
  pt::test::write_text(dir + "/cam.txt", kCamera);
  pt::test::write_text(dir + "/cam_zero.txt", kCameraZero);
  pt::test::write_text(dir + "/cam_nan.txt", kCameraNan);
  pt::test::write_text(dir + "/sky.exr", sky);
  pt::test::write_text(dir + "/short.exr", sky.substr(0, sky.size() / 2));
  pt::test::write_text(dir + "/empty.exr", "");
}

// ---- Command lines -----------------------------------------------------------

struct Command {
  std::vector<std::string> args;
  std::vector<std::string> inputs;   // files of ../inputs this run reads
  std::vector<std::string> outputs;  // outputs a successful run must leave
  std::vector<std::string> folders;  // obstacles made in the work folder first
};

// Values that must be refused, or that are valid and cheap.
std::string number(Random& rng, const std::vector<std::string>& good, const std::vector<std::string>& bad) {
  return rng.chance(0.8) ? rng.pick(good) : rng.pick(bad);
}

const std::vector<std::string> kBadInts = {"0", "-1", "-2147483648", "2147483648", "99999999999999999999", "x", "",
                                           "1.5", "nan", "inf", "1e3", "0x", " 1", "--1"};
const std::vector<std::string> kBadReals = {"nan", "NaN", "-nan", "inf", "-inf", "1e999", "-1", "x", "", "1e", "--1",
                                            "0x1p99999"};

// Output paths, relative to the work folder (the current folder of a run).
const std::vector<std::string> kOutputs = {
    "o.png",          "o.pfm",     "o.json",           "./o.png",     "o_rate.png", "sub/o.png", "missing/o.png",
    "o",              "o.png/",    "",                 ".",           "..",         "obstacle",  "../inputs/tiny.dae",
    "../inputs/cam.txt", "../inputs/sky.exr", "../inputs/folder", "../inputs/ball.dae",
    std::string(300, 'n') + ".png", std::string(250, 'm') + ".png"};

Command make_command(Random& rng) {
  Command c;
  auto add = [&](std::initializer_list<std::string> a) { c.args.insert(c.args.end(), a); };
  // Scene.
  std::string scene = "../inputs/tiny.dae";
  const double s = double(rng.below(1000)) / 1000;
  if (s < 0.08) scene = "../inputs/ball.dae";
  else if (s < 0.11) scene = "../inputs/garbage.dae";
  else if (s < 0.13) scene = "../inputs/empty.dae";
  else if (s < 0.15) scene = "../inputs/missing.dae";
  else if (s < 0.16) scene = "../inputs/folder";
  else if (s < 0.17) scene = "";
  else if (s < 0.20) scene = fs::absolute("../inputs/tiny.dae").lexically_normal().string();
  c.inputs.push_back(scene);

  // Size: always a tiny one, or one that must be refused.
  int w = rng.in(1, 16), h = rng.in(1, 12);
  if (rng.chance(0.1)) {
    const std::vector<std::pair<std::string, std::string>> bad = {
        {"0", "4"}, {"4", "-1"}, {"16385", "1"}, {"16384", "16384"}, {"8192", "4097"}, {"x", "4"}, {"4", ""},
        {"2147483648", "1"}};
    const auto& b = rng.pick(bad);
    add({"-r", b.first, b.second});
  } else {
    add({"-r", std::to_string(w), std::to_string(h)});
  }
  const auto maybe = [&](double p) { return rng.chance(p); };
  if (maybe(0.3)) add({"-s", number(rng, {"1", "2", "3", "4"}, kBadInts)});
  if (maybe(0.2)) add({"-l", number(rng, {"1", "2"}, kBadInts)});
  if (maybe(0.2)) add({"-t", number(rng, {"1", "2", "3"}, kBadInts)});
  if (maybe(0.2)) add({"-m", number(rng, {"0", "1", "2", "5", "1000"}, kBadInts)});
  if (maybe(0.1)) add({"-o", number(rng, {"0", "1", "7"}, kBadInts)});
  if (maybe(0.2)) add({"--part", number(rng, {"1", "2", "3", "4", "5", "6", "7", "8", "9"}, {"0", "10", "-1", "x", ""})});
  if (maybe(0.15)) add({"-b", number(rng, {"0", "0.05", "1e6"}, kBadReals)});
  if (maybe(0.15)) add({"-d", number(rng, {"1", "4.7", "1e-6", "1e9"}, kBadReals)});
  if (maybe(0.15)) {
    const std::vector<std::pair<std::string, std::string>> good = {{"4", "0.05"}, {"1", "1e-9"}, {"64", "1"}};
    const std::vector<std::pair<std::string, std::string>> bad = {
        {"0", "0.1"}, {"4", "nan"}, {"4", "-1"}, {"x", "y"}, {"4", "inf"}, {"99999999999", "1"}, {"4", ""}};
    const auto& v = rng.chance(0.7) ? rng.pick(good) : rng.pick(bad);
    add({"-a", v.first, v.second});
  }
  if (maybe(0.15)) {
    if (rng.chance(0.6)) {
      const int x = rng.in(0, w - 1), y = rng.in(0, h - 1);
      add({"-p", std::to_string(x), std::to_string(y), std::to_string(rng.in(1, w - x)),
           std::to_string(rng.in(1, h - y))});
    } else {
      const std::vector<std::vector<std::string>> bad = {
          {"2147483600", "0", "100", "1"}, {"0", "2147483600", "1", "100"}, {"0", "0", "2147483647", "1"},
          {"-1", "0", "1", "1"},            {"0", "0", "0", "1"},            {"0", "0", "1"},
          {"0", "0", "99", "99"},           {"x", "0", "1", "1"}};
      const auto& v = rng.pick(bad);
      c.args.push_back("-p");
      c.args.insert(c.args.end(), v.begin(), v.end());
    }
  }
  if (maybe(0.15))
    add({"--seed", number(rng, {"0", "7", "18446744073709551615"},
                          {"-1", "18446744073709551616", "x", "", "1.0", "+-3", "0x10"})});
  if (maybe(0.1)) add({"--bvh-leaf", number(rng, {"1", "4", "255"}, {"0", "256", "-1", "x"})});
  if (maybe(0.1)) add({"--bvh-bins", number(rng, {"2", "12", "64"}, {"1", "65", "x"})});
  if (maybe(0.15)) {
    const std::string e = rng.pick(std::vector<std::string>{"../inputs/sky.exr", "../inputs/sky.exr", "../inputs/short.exr",
                                                            "../inputs/empty.exr", "../inputs/tiny.dae",
                                                            "../inputs/missing.exr", "../inputs/folder", ""});
    add({"-e", e});
    c.inputs.push_back(e);
  }
  if (maybe(0.15)) {
    const std::string f = rng.pick(std::vector<std::string>{"../inputs/cam.txt", "../inputs/cam.txt",
                                                            "../inputs/cam_zero.txt", "../inputs/cam_nan.txt",
                                                            "../inputs/missing.txt", "../inputs/tiny.dae", ""});
    add({"-c", f});
    c.inputs.push_back(f);
  }
  for (const char* flag : {"-H", "--no-rr", "--direct-only", "--indirect-only", "--course-area-pdf", "--no-progress"})
    if (maybe(0.08)) c.args.push_back(flag);

  // Outputs: mostly well-formed, sometimes hostile.
  std::string png;
  if (maybe(0.85)) {
    png = rng.chance(0.75) ? "o.png" : rng.pick(kOutputs);
    add({"-f", png});
  } else {
    png = fs::path(scene).stem().string() + ".png";
  }
  c.outputs.push_back(png);
  if (png.size() >= 4 && png.compare(png.size() - 4, 4, ".png") == 0)
    c.outputs.push_back(png.substr(0, png.size() - 4) + "_rate.png");
  else
    c.outputs.push_back(png + "_rate.png");
  if (maybe(0.3)) {
    const std::string p = rng.chance(0.6) ? "o.pfm" : rng.pick(kOutputs);
    add({"--pfm", p});
    c.outputs.push_back(p);
  }
  if (maybe(0.25)) {
    const std::string j = rng.chance(0.6) ? "o.json" : rng.pick(kOutputs);
    add({"--stats-json", j});
    c.outputs.push_back(j);
  }
  // Obstacles: a folder where an output goes, or a folder for sub/.
  if (maybe(0.1)) c.folders.push_back(rng.pick(std::vector<std::string>{"o.png", "o_rate.png", "o.pfm", "o.json"}));
  if (maybe(0.3)) c.folders.push_back("sub");
  c.folders.push_back("obstacle");
  // Junk.
  if (maybe(0.04)) c.args.push_back(rng.pick(std::vector<std::string>{"--bogus", "-z", "-", "--", "-s", "extra.dae"}));

  // Shuffle the flags (keeping each flag with its values), scene last mostly.
  std::vector<std::vector<std::string>> groups;
  for (const std::string& a : c.args) {
    const bool flag = a.size() > 1 && a[0] == '-' && !std::isdigit(static_cast<unsigned char>(a[1])) &&
                      a != "-inf" && a != "-nan" && a != "--1";
    if (flag || groups.empty()) groups.push_back({a});
    else groups.back().push_back(a);
  }
  for (size_t i = groups.size(); i > 1; --i) std::swap(groups[i - 1], groups[rng.below(i)]);
  c.args.clear();
  for (const auto& g : groups) c.args.insert(c.args.end(), g.begin(), g.end());
  if (rng.chance(0.95)) c.args.push_back(scene);
  else c.args.insert(c.args.begin(), scene);
  return c;
}

std::string shown(const std::vector<std::string>& args) {
  std::string s = "pathtracer";
  for (const std::string& a : args) s += a.empty() ? " ''" : " " + (a.size() > 40 ? a.substr(0, 12) + "..." : a);
  return s;
}

// The contract of one run. Returns what was broken, or "".
std::string check(const Command& c, const Run& r, const std::map<std::string, std::string>& inputs_before,
                  const std::map<std::string, std::string>& inputs_after,
                  const std::map<std::string, std::string>& work_before,
                  const std::map<std::string, std::string>& work_after) {
  if (r.hung) return "hung (killed after the time limit)";
  if (r.status >= 128) return "killed by signal " + std::to_string(r.status - 128);
  if (r.status != 0 && r.status != 1 && r.status != 2) return "exit status " + std::to_string(r.status);
  for (const auto* files : {&inputs_after, &work_after})
    for (const auto& [name, bytes] : *files)
      if (name.find(".tmp.") != std::string::npos) return "a temporary file was left behind: " + name;
  // The inputs this run read are never changed.
  for (const std::string& in : c.inputs) {
    const std::string rel = in.rfind("../inputs/", 0) == 0 ? in.substr(10) : fs::path(in).filename().string();
    const auto a = inputs_before.find(rel), b = inputs_after.find(rel);
    if (a != inputs_before.end() && (b == inputs_after.end() || a->second != b->second))
      return "an input was changed: " + rel;
  }
  const std::vector<std::string> err = lines_of(r.err);
  int errors = 0;
  for (size_t i = 0; i < err.size(); ++i) {
    if (err[i].rfind("pathtracer: error: ", 0) == 0) ++errors;
    // Warnings, and in the student starter kit the stubs' "TODO: implement"
    // lines, may come before the error.
    else if (err[i].rfind("pathtracer: warning: ", 0) != 0 && err[i].rfind("TODO: implement ", 0) != 0)
      return "an unexpected line on stderr: " + err[i];
  }
  if (r.status != 0) {
    if (errors != 1 || err.back().rfind("pathtracer: error: ", 0) != 0)
      return "a failure without exactly one error line at the end of stderr";
    if (r.status == 2 && !r.out.empty()) return "a refused command line printed on stdout";
    if (inputs_after != inputs_before) return "a failed run changed the inputs folder";
    if (work_after != work_before) return "a failed run left files behind";
    return "";
  }
  if (errors != 0) return "an error line in a successful run";
  for (const std::string& out : c.outputs) {
    std::error_code ec;
    if (!fs::is_regular_file(out, ec) || fs::file_size(out, ec) == 0) return "an output is missing or empty: " + out;
  }
  for (size_t i = 0; i < 2; ++i)  // the image and its rate image
    if (slurp(c.outputs[i]).compare(0, 8, "\x89PNG\r\n\x1a\n") != 0) return "not a PNG: " + c.outputs[i];
  return "";
}

int usage(const char* msg) {
  std::fprintf(stderr, "fuzz_cli: %s\nusage: fuzz_cli [--seed N] [--runs N] [--seconds S] [--timeout S] [--pathtracer EXE]\n",
               msg);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  uint64_t seed = 1;
  long long runs = -1;
  double seconds = -1;
  unsigned timeout = 30;
  std::string exe = PT_PATHTRACER_EXE;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 >= argc) return usage((a + " needs a value").c_str());
    const std::string v = argv[++i];
    try {
      if (a == "--seed") seed = std::stoull(v);
      else if (a == "--runs") runs = std::stoll(v);
      else if (a == "--seconds") seconds = std::stod(v);
      else if (a == "--timeout") timeout = unsigned(std::stoul(v));
      else if (a == "--pathtracer") exe = fs::absolute(v).string();
      else return usage(("unknown option " + a).c_str());
    } catch (const std::exception& e) {
      return usage(e.what());
    }
  }
  if (runs < 0 && seconds < 0) runs = 300;

  pt::test::TempDir root;
  const std::string inputs = root.file("inputs"), work = root.file("work"), io = root.file("io");
  fs::create_directories(io);
  const std::string sky = slurp(pt::test::project_scene("sky_bands.exr"));
  if (sky.empty()) return usage("scenes/sky_bands.exr not found");

  Random rng(seed);
  std::map<std::string, long long> outcomes;
  long long by_status[4] = {0, 0, 0, 0};
  int broken = 0;
  double slowest = 0;
  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  long long n = 0;
  for (; runs < 0 || n < runs; ++n) {
    if (seconds >= 0 && elapsed() >= seconds) break;
    std::error_code ec;
    fs::remove_all(inputs, ec);
    fs::remove_all(work, ec);
    write_inputs(inputs, sky);
    fs::create_directories(work);
    fs::current_path(work);  // relative paths of the command resolve here, as in the run
    const Command c = make_command(rng);
    for (const std::string& f : c.folders) fs::create_directories(work + "/" + f);
    const auto inputs_before = snapshot(inputs), work_before = snapshot(work);
    const auto r0 = std::chrono::steady_clock::now();
    const Run r = run(exe, c.args, work, io, timeout);
    slowest = std::max(slowest, std::chrono::duration<double>(std::chrono::steady_clock::now() - r0).count());
    const std::string problem = check(c, r, inputs_before, snapshot(inputs), work_before, snapshot(work));
    if (r.status >= 0 && r.status <= 2) ++by_status[r.status];
    else ++by_status[3];
    std::string key = "exit " + std::to_string(r.status);
    const std::vector<std::string> err = lines_of(r.err);
    if (r.status != 0 && !err.empty()) key += ": " + shape(err.back());
    ++outcomes[key];
    if (!problem.empty()) {
      ++broken;
      std::printf("fuzz_cli: run %lld: %s\n  %s\n  exit %d, stderr: %s\n", n, problem.c_str(), shown(c.args).c_str(),
                  r.status, r.err.substr(0, 400).c_str());
    }
  }
  fs::current_path(root.path());
  const double total = elapsed();
  std::printf("fuzz_cli: seed %llu: %lld runs in %.1f s (%.0f per second): exit 0: %lld, 1: %lld, 2: %lld, other: "
              "%lld; %zu distinct outcomes; slowest run %.2f s; %d broke the contract\n",
              (unsigned long long)seed, n, total, total > 0 ? double(n) / total : 0.0, by_status[0], by_status[1],
              by_status[2], by_status[3], outcomes.size(), slowest, broken);
  if (std::getenv("PT_FUZZ_VERBOSE"))
    for (const auto& [key, count] : outcomes) std::printf("  %6lld  %s\n", count, key.c_str());
  return broken == 0 ? 0 : 1;
}
