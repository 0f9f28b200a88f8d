// A seeded mutation fuzzer for the readers of untrusted files: the COLLADA
// loader (load_collada), the camera settings file (-c, Camera::load_settings)
// and the OpenEXR environment map (-e, load_environment_map). It is built
// with AddressSanitizer and UndefinedBehaviorSanitizer (see CMakeLists.txt),
// so a memory error or undefined behaviour aborts the run with a report.
//
// Each iteration takes a seed file, applies a few random mutations (bit
// flips, deletions, duplications, splices, tokens and numbers from a
// dictionary, duplicated XML elements, rewired references, header integers),
// writes the result to a file and reads it. Beyond the sanitizers it checks
// the readers' contract: an input is either read, giving a scene (or camera,
// or map) whose numbers are finite and consistent, or refused with the
// documented exception whose message is one line starting with the file's
// path; warnings are one line starting with the path. A scene that loads
// also gets a BVH (part 2's build, sanitized too) and a few rays through it.
// The same seed gives
// the same inputs, so a finding can be replayed.
//
//   fuzz_loaders [--seed N] [--iterations N] [--seconds S] [--max-seed-bytes N]
//                [--timeout S] [--work DIR] [--skip-without PATH] INPUT...
//
// INPUTs are files or folders (whose .dae, .exr and .txt files are taken);
// one that does not exist is an error, so that a run's seed set never
// changes silently. --skip-without PATH makes the run exit with 77 (ctest's
// "skipped") when PATH is absent: the run over the course's scenes, which
// may not be beside the checkout, is its own test. .dae files are scenes,
// .exr files environment maps, anything else a camera settings file. Seeds
// larger than --max-seed-bytes (default 400000) are read once unmutated but
// not mutated. Exit status 0 when nothing was found, 1 on a finding, 2 on
// bad arguments, 77 when skipped.
//
// This file is the driver (the command line, the seeds' first reading, the
// loop and its report, saving the input a crash or hang happened on); the
// random numbers and kinds of input are in loader_inputs.h, the mutations in
// loader_mutations.cpp, the readers and their contract in loader_checks.cpp,
// the seed files in loader_seeds.cpp.
#include <sanitizer/common_interface_defs.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "instructors/fuzz/loader_checks.h"
#include "instructors/fuzz/loader_inputs.h"
#include "instructors/fuzz/loader_mutations.h"
#include "instructors/fuzz/loader_seeds.h"

namespace fs = std::filesystem;
using namespace fuzz;

namespace {

// ---- What is being read, for a report if the process dies ----------------

std::string g_current_input;  // the file being read
std::string g_current_label;  // "iteration 12 (dae, from CBempty.dae)"
uint64_t g_seed = 1;

void save_current_input(const char* why) {
  if (g_current_input.empty()) return;
  const std::string keep = "fuzz-finding" + fs::path(g_current_input).extension().string();
  std::error_code ec;
  fs::copy_file(g_current_input, keep, fs::copy_options::overwrite_existing, ec);
  std::fprintf(stderr, "fuzz_loaders: %s while reading %s, seed %llu; the input is saved as %s\n", why,
               g_current_label.c_str(), (unsigned long long)g_seed, ec ? g_current_input.c_str() : keep.c_str());
}

void on_sanitizer_death() { save_current_input("sanitizer report"); }
void on_terminate() {
  save_current_input("std::terminate");
  std::abort();
}
void on_alarm(int) {
  save_current_input("time limit exceeded (a hang)");
  std::_Exit(1);
}

int usage(const char* msg) {
  std::fprintf(stderr,
               "fuzz_loaders: %s\nusage: fuzz_loaders [--seed N] [--iterations N] [--seconds S] "
               "[--max-seed-bytes N] [--timeout S] [--work DIR] [--skip-without PATH] INPUT...\n",
               msg);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  uint64_t seed = 1;
  long long iterations = -1;
  double seconds = -1;
  size_t max_seed_bytes = 400000;
  unsigned timeout = 60;
  std::string work;
  std::vector<std::string> inputs, required;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
      return argv[++i];
    };
    try {
      if (a == "--seed") seed = std::stoull(value());
      else if (a == "--iterations") iterations = std::stoll(value());
      else if (a == "--seconds") seconds = std::stod(value());
      else if (a == "--max-seed-bytes") max_seed_bytes = std::stoull(value());
      else if (a == "--timeout") timeout = unsigned(std::stoul(value()));
      else if (a == "--work") work = value();
      else if (a == "--skip-without") required.push_back(value());
      else if (a.rfind("--", 0) == 0) return usage(("unknown option " + a).c_str());
      else inputs.push_back(a);
    } catch (const std::exception& e) {
      return usage(e.what());
    }
  }
  if (iterations < 0 && seconds < 0) iterations = 1000;
  // A run over optional seeds (the course's scenes) is skipped, exit code 77
  // for ctest, when they are absent: their presence adds a run of its own
  // and never changes which inputs another seeded run tries.
  for (const std::string& path : required) {
    std::error_code ec;
    if (!fs::exists(path, ec)) {
      std::printf("fuzz_loaders: skipped: %s is absent (this run mutates the files there)\n", path.c_str());
      return 77;
    }
  }
  g_seed = seed;
  __sanitizer_set_death_callback(on_sanitizer_death);
  std::set_terminate(on_terminate);
  signal(SIGALRM, on_alarm);

  bool own_work = false;
  if (work.empty()) {
    std::string tmpl = (fs::temp_directory_path() / "pt-fuzz-XXXXXX").string();
    if (!mkdtemp(tmpl.data())) return usage("cannot create a work folder");
    work = tmpl;
    own_work = true;
  }
  fs::create_directories(work);

  g_current_label = "the fixed BVH probes";
  if (const std::string finding = probe_bvh_extremes(); !finding.empty()) {
    std::fprintf(stderr, "fuzz_loaders: finding in %s: %s\n", g_current_label.c_str(), finding.c_str());
    return 1;
  }

  // Seeds: the inputs, and generated EXR files.
  std::vector<Seed> seeds;
  for (const std::string& in : inputs) {
    std::error_code ec;
    if (fs::is_directory(in, ec)) {
      std::vector<fs::path> files;
      for (const auto& e : fs::directory_iterator(in)) {
        const std::string ext = e.path().extension().string();
        if (ext == ".dae" || ext == ".exr" || ext == ".txt") files.push_back(e.path());
      }
      std::sort(files.begin(), files.end());  // a fixed order: the run depends on it
      for (const fs::path& p : files) seeds.push_back({p.filename().string(), kind_of(p), slurp(p.string())});
    } else if (fs::is_regular_file(in, ec)) {
      seeds.push_back({fs::path(in).filename().string(), kind_of(in), slurp(in)});
    } else {
      return usage((in + " does not exist").c_str());
    }
  }
  write_exr_seeds(work, &seeds);

  // Every seed must read cleanly before it is mutated.
  int findings = 0;
  Random check_rng(seed);
  std::vector<Seed> pool;
  for (const Seed& s : seeds) {
    const std::string path = work + "/seed" + kind_ext(s.kind);
    std::ofstream(path, std::ios::binary) << s.bytes;
    g_current_input = path;
    g_current_label = "seed " + s.name;
    alarm(timeout);
    const Outcome o = read_input(s.kind, path, check_rng);
    alarm(0);
    if (o.key.find(" loaded") == std::string::npos || o.key.find("warnings") != std::string::npos ||
        !o.finding.empty()) {
      std::printf("fuzz_loaders: seed %s does not read cleanly: %s %s\n", s.name.c_str(), o.key.c_str(),
                  o.finding.c_str());
      ++findings;
    }
    if (s.bytes.size() <= max_seed_bytes) pool.push_back(s);
  }
  bool have[3] = {false, false, false};
  for (const Seed& s : pool) have[int(s.kind)] = true;

  Random rng(seed);
  std::map<std::string, long long> outcomes;
  long long per_kind[3] = {0, 0, 0}, loaded[3] = {0, 0, 0};
  double kind_seconds[3] = {0, 0, 0};
  double slowest = 0;
  std::string slowest_label;
  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  long long it = 0;
  for (; iterations < 0 || it < iterations; ++it) {
    if (seconds >= 0 && elapsed() >= seconds) break;
    // Scenes most often: they have the most structure.
    const double r = rng.uniform();
    Kind kind = r < 0.6 ? Kind::Scene : r < 0.85 ? Kind::Exr : Kind::Camera;
    if (!have[int(kind)]) kind = have[0] ? Kind::Scene : have[2] ? Kind::Exr : Kind::Camera;
    std::vector<const Seed*> same;
    for (const Seed& s : pool)
      if (s.kind == kind) same.push_back(&s);
    if (same.empty()) return usage("no seed to mutate");
    const Seed& from = *same[rng.below(same.size())];
    std::string bytes = from.bytes;
    mutate(rng, bytes, kind, pool);

    const std::string path = work + "/input" + kind_ext(kind);
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
    g_current_input = path;
    g_current_label = "iteration " + std::to_string(it) + " (" + kind_name(kind) + ", from " + from.name + ")";
    const auto s0 = std::chrono::steady_clock::now();
    alarm(timeout);
    const Outcome o = read_input(kind, path, rng);
    alarm(0);
    const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - s0).count();
    if (std::getenv("PT_FUZZ_SLOW") && took > std::atof(std::getenv("PT_FUZZ_SLOW"))) {
      std::printf("fuzz_loaders: slow input: %s took %.3f s: %s\n", g_current_label.c_str(), took, o.key.c_str());
      std::error_code ec;
      fs::copy_file(path, "fuzz-slow-" + std::to_string(it) + kind_ext(kind), fs::copy_options::overwrite_existing, ec);
    }
    if (took > slowest) {
      slowest = took;
      slowest_label = g_current_label;
    }
    ++per_kind[int(kind)];
    kind_seconds[int(kind)] += took;
    if (o.key.find(" loaded") != std::string::npos) ++loaded[int(kind)];
    ++outcomes[o.key];
    if (!o.finding.empty()) {
      ++findings;
      std::printf("fuzz_loaders: FINDING at %s: %s\n", g_current_label.c_str(), o.finding.c_str());
      std::error_code ec;
      fs::copy_file(path, "fuzz-finding-" + std::to_string(it) + kind_ext(kind), fs::copy_options::overwrite_existing, ec);
    }
  }
  g_current_input.clear();
  const double total = elapsed();

  std::printf("fuzz_loaders: seed %llu: %lld inputs in %.1f s (%.0f per second): %lld scenes (%lld read, %.1f s), "
              "%lld environment maps (%lld read, %.1f s), %lld camera files (%lld read, %.1f s)\n",
              (unsigned long long)seed, it, total, total > 0 ? double(it) / total : 0.0, per_kind[0], loaded[0],
              kind_seconds[0], per_kind[2], loaded[2], kind_seconds[2], per_kind[1], loaded[1], kind_seconds[1]);
  std::printf("fuzz_loaders: %zu distinct outcomes; slowest input %.2f s (%s); %d finding%s\n", outcomes.size(),
              slowest, slowest_label.c_str(), findings, findings == 1 ? "" : "s");
  if (std::getenv("PT_FUZZ_VERBOSE"))
    for (const auto& [key, n] : outcomes) std::printf("  %6lld  %s\n", n, key.c_str());
  if (own_work && findings == 0) {
    std::error_code ec;
    fs::remove_all(work, ec);
  }
  return findings == 0 ? 0 : 1;
}
