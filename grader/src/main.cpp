// grader: renders the canonical cases with any pathtracer build, scores them
// against the committed references and writes the reports. See
// grader/README.md for the commands, the scoring and the exit codes.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

#include "case_list.h"
#include "clock.h"
#include "compare.h"
#include "grade.h"
#include "image_io.h"
#include "reference.h"
#include "reports.h"
#include "text.h"

namespace fs = std::filesystem;
using namespace grader;


namespace {

// Exit codes.
constexpr int kAllPassed = 0, kSomeFailed = 1, kUsageError = 2;

std::string executable_dir() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string(".") : self.parent_path().string();
}

// The options every command shares.
struct Common {
  std::string pathtracer = executable_dir() + "/pathtracer";
  std::string cases = std::string(PT_SOURCE_DIR) + "/grader/cases.txt";
  std::string references = std::string(PT_SOURCE_DIR) + "/reference_images";
  std::string scenes = std::string(PT_SOURCE_DIR) + "/scenes";
  std::vector<int> parts;
  std::vector<std::string> names;
  std::string shard;  // "K/N"
  int jobs = 2;
  int threads = 1;
  double timeout_scale = 1.0;
  int memory_mb = 4096;
  int output_mb = 256;

  void add_to(CLI::App* app, bool with_binary) {
    if (with_binary) app->add_option("--pathtracer", pathtracer, "The pathtracer binary to run")->capture_default_str();
    app->add_option("--cases", cases, "The case list")->capture_default_str();
    app->add_option("--references", references, "The reference folder")->capture_default_str();
    app->add_option("--scenes", scenes, "Where the cases' scenes are")->capture_default_str();
    app->add_option("--part", parts, "Only these parts (repeatable)")->check(CLI::Range(1, 5));
    app->add_option("--case", names, "Only these cases (repeatable)");
    app->add_option("--shard", shard, "K/N: only the K-th of N equal slices of the cases (K = 1..N)");
    app->add_option("-j,--jobs", jobs, "Cases (or renders) at a time")->check(CLI::Range(1, 256))->capture_default_str();
    app->add_option("-t,--threads", threads, "Threads per render (-t)")->check(CLI::Range(1, 256))->capture_default_str();
    app->add_option("--timeout-scale", timeout_scale, "Multiply every case's timeout (slow machines)")
        ->check(CLI::Range(0.01, 1000.0))->capture_default_str();
    app->add_option("--memory-mb", memory_mb, "Address-space limit per render")->check(CLI::Range(64, 1 << 20))->capture_default_str();
    app->add_option("--output-mb", output_mb, "Output-size limit per render")->check(CLI::Range(1, 1 << 20))->capture_default_str();
  }

  RunSettings run_settings() const {
    RunSettings s;
    s.pathtracer = pathtracer;
    s.scenes_dir = scenes;
    s.threads = threads;
    s.timeout_scale = timeout_scale;
    s.memory_bytes = uint64_t(memory_mb) << 20;
    s.output_bytes = uint64_t(output_mb) << 20;
    return s;
  }

  // The selected cases. Throws std::runtime_error on a bad file or filter.
  std::vector<Case> select() const {
    std::vector<Case> all = read_cases(cases);
    std::set<std::string> known;
    for (const Case& c : all) known.insert(c.name);
    for (const std::string& n : names)
      if (!known.count(n)) throw std::runtime_error(cases + ": no case named '" + n + "'");
    std::vector<Case> chosen;
    for (const Case& c : all) {
      if (!parts.empty() && std::find(parts.begin(), parts.end(), c.part) == parts.end()) continue;
      if (!names.empty() && std::find(names.begin(), names.end(), c.name) == names.end()) continue;
      chosen.push_back(c);
    }
    if (!shard.empty()) {
      int k = 0, n = 0;
      char slash = 0;
      std::istringstream in(shard);
      if (!(in >> k >> slash >> n) || slash != '/' || n < 1 || k < 1 || k > n || !in.eof())
        throw std::runtime_error("--shard " + shard + ": expected K/N with 1 <= K <= N");
      std::vector<Case> mine;
      for (size_t i = 0; i < chosen.size(); ++i)
        if (int(i % size_t(n)) == k - 1) mine.push_back(chosen[i]);
      chosen = mine;
    }
    return chosen;
  }

  void check_binary() const {
    // access() alone accepts a directory (X_OK is search permission there).
    std::error_code ec;
    if (!fs::is_regular_file(pathtracer, ec) || access(pathtracer.c_str(), X_OK) != 0)
      throw std::runtime_error(pathtracer + ": not an executable file");
  }
};

// Runs `task(i)` for i in [0, n) on `jobs` threads.
template <class F>
void parallel_for(int n, int jobs, F task) {
  std::atomic<int> next{0};
  std::vector<std::thread> pool;
  for (int j = 0; j < std::max(1, std::min(jobs, n)); ++j)
    pool.emplace_back([&] {
      for (int i; (i = next.fetch_add(1)) < n;) task(i);
    });
  for (auto& t : pool) t.join();
}

int exit_code_for(const std::vector<CaseResult>& results) {
  int code = kAllPassed;
  for (const auto& r : results) {
    if (r.verdict == Verdict::Error) return kUsageError;
    if (r.verdict == Verdict::Failed) code = kSomeFailed;
  }
  return code;
}

int command_run(const Common& common, const std::string& out, uint64_t seed, bool quiet) {
  const auto t0 = pt::Clock::now();
  const std::string started = utc_now();
  const std::vector<Case> cases = common.select();
  common.check_binary();
  fs::create_directories(out + "/cases");
  std::vector<CaseResult> results(cases.size());
  std::mutex mu;
  int done = 0;
  const RunSettings run = common.run_settings();
  const CostBounds bounds;
  parallel_for(int(cases.size()), common.jobs, [&](int i) {
    const Case& c = cases[size_t(i)];
    const std::string dir = out + "/cases/" + c.name;
    CaseResult r;
    try {
      r = grade_case(run, common.references, c, seed, dir, bounds);
    } catch (const std::exception& e) {
      r.c = c;
      r.max_score = c.points;
      r.verdict = Verdict::Error;
      r.message = std::string("grader error: ") + e.what();
      r.dir = dir;
    }
    try {
      fs::create_directories(dir);
      write_text(dir + "/result.json", case_result_json(r));
    } catch (const std::exception& e) {
      std::fprintf(stderr, "grader: %s\n", e.what());
    }
    std::lock_guard<std::mutex> lock(mu);
    results[size_t(i)] = r;
    ++done;
    if (!quiet)
      std::printf("[%2d/%zu] %-24s %-7s %6.1f s  %s\n", done, cases.size(), c.name.c_str(), verdict_name(r.verdict),
                  r.seconds, r.verdict == Verdict::Passed ? "" : r.message.c_str());
    std::fflush(stdout);
  });
  RunInfo info;
  info.pathtracer = fs::absolute(common.pathtracer).string();
  info.started = started;
  info.wall_seconds = pt::seconds_since(t0);
  info.jobs = common.jobs;
  info.threads = common.threads;
  info.seed = seed;
  write_reports(out, results, info);
  std::printf("\n%s", terminal_table(results).c_str());
  std::printf("Reports: %s/{report.txt,timing.md,results.json,report.html} (%.0f s)\n", out.c_str(),
              info.wall_seconds);
  return exit_code_for(results);
}

int command_merge(const Common& common, const std::string& out, const std::vector<std::string>& shard_dirs) {
  std::vector<CaseResult> results;
  std::set<std::string> seen;
  for (const std::string& d : shard_dirs) {
    if (!fs::is_directory(d + "/cases")) throw std::runtime_error(d + ": not a grader output folder (no cases/)");
    for (const auto& entry : fs::directory_iterator(d + "/cases")) {
      const std::string path = entry.path().string() + "/result.json";
      if (!fs::exists(path)) continue;
      CaseResult r;
      if (!case_result_from_json(pt::read_json_file(path), &r)) throw std::runtime_error(path + ": not a case result");
      if (!seen.insert(r.c.name).second) throw std::runtime_error(path + ": case " + r.c.name + " graded twice");
      results.push_back(r);
    }
  }
  // In the case list's order when it is readable, else by part and name.
  std::map<std::string, int> order;
  try {
    const std::vector<Case> all = read_cases(common.cases);
    for (size_t i = 0; i < all.size(); ++i) order[all[i].name] = int(i);
  } catch (const std::exception&) {
  }
  std::stable_sort(results.begin(), results.end(), [&](const CaseResult& a, const CaseResult& b) {
    const int ia = order.count(a.c.name) ? order[a.c.name] : 1 << 30, ib = order.count(b.c.name) ? order[b.c.name] : 1 << 30;
    return ia != ib ? ia < ib : (a.c.part != b.c.part ? a.c.part < b.c.part : a.c.name < b.c.name);
  });
  fs::create_directories(out);
  RunInfo info;
  info.pathtracer = "(merged from " + std::to_string(shard_dirs.size()) + " shards)";
  info.started = utc_now();
  for (const auto& r : results) info.wall_seconds += r.seconds;
  write_reports(out, results, info);
  std::printf("%s", terminal_table(results).c_str());
  return exit_code_for(results);
}

std::string git_commit() {
  FILE* p = popen(("git -C '" + std::string(PT_SOURCE_DIR) + "' rev-parse --short HEAD 2>/dev/null").c_str(), "r");
  if (!p) return "unknown";
  char buf[64] = {0};
  const bool ok = std::fgets(buf, sizeof buf, p) != nullptr;
  pclose(p);
  std::string s = ok ? buf : "unknown";
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r')) s.pop_back();
  return s;
}

int command_make_references(const Common& common, int runs, bool force, int retime, const std::string& work) {
  const std::vector<Case> cases = common.select();
  common.check_binary();
  MakeSettings ms;
  ms.run = common.run_settings();
  ms.run.timeout_scale *= 3;  // never lose a long reference run to a tight case timeout
  ms.runs = runs;
  ms.jobs = common.jobs;
  ms.force = force;
  ms.commit = git_commit();
  ms.work_dir = work;
  fs::create_directories(work);
  fs::create_directories(common.references);
  int failures = 0;
  for (size_t i = 0; i < cases.size(); ++i) {
    std::string message;
    const bool ok = retime > 0 ? retime_reference(common.references, cases[i], ms, retime, &message)
                               : make_reference(common.references, cases[i], ms, &message);
    failures += !ok;
    std::printf("[%2zu/%zu] %-24s %s%s\n", i + 1, cases.size(), cases[i].name.c_str(), ok ? "" : "FAILED: ",
                message.c_str());
    std::fflush(stdout);
  }
  return failures ? kSomeFailed : kAllPassed;
}

// The one-sided 95 % upper confidence bound (Clopper-Pearson) on a rate
// after k events in n trials: the p with P(X <= k | n, p) = 0.05.
double rate_upper_bound(int k, int n) {
  if (n <= 0 || k >= n) return 1.0;
  const auto cdf = [&](double p) {
    double term = std::pow(1 - p, n), sum = term;  // P(X = 0), then the next terms
    for (int i = 1; i <= k; ++i) {
      term *= double(n - i + 1) / i * p / (1 - p);
      sum += term;
    }
    return sum;
  };
  double lo = 0, hi = 1;
  for (int it = 0; it < 100; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (cdf(mid) > 0.05) lo = mid;
    else hi = mid;
  }
  return hi;
}

int command_calibrate(const Common& common, int seeds, uint64_t first_seed, const std::string& table,
                      const std::string& work) {
  const std::vector<Case> cases = common.select();
  common.check_binary();
  struct Task {
    size_t case_index;
    uint64_t seed;
  };
  std::vector<Task> tasks;
  std::vector<bool> deterministic(cases.size(), false);
  for (size_t i = 0; i < cases.size(); ++i) {
    Reference ref;
    std::string why;
    if (!load_reference(common.references, cases[i], &ref, &why)) throw std::runtime_error(cases[i].name + ": " + why);
    deterministic[i] = ref.deterministic;
    // A deterministic image does not depend on the seed: one run says it all.
    const int n = ref.deterministic ? 1 : seeds;
    for (int s = 0; s < n; ++s) tasks.push_back({i, first_seed + uint64_t(s)});
  }
  struct Tally {
    int runs = 0, failures = 0;
    double worst_relmse_ratio = 0, seconds = 0;
    std::vector<std::string> failed_messages;
  };
  std::vector<Tally> tally(cases.size());
  std::mutex mu;
  std::atomic<int> done{0};
  const RunSettings run = common.run_settings();
  const auto t0 = pt::Clock::now();
  parallel_for(int(tasks.size()), common.jobs, [&](int t) {
    const Task& task = tasks[size_t(t)];
    const Case& c = cases[task.case_index];
    const std::string dir = work + "/" + c.name + "_" + std::to_string(task.seed);
    CaseResult r = grade_case(run, common.references, c, task.seed, dir, CostBounds());
    std::error_code ec;
    fs::remove_all(dir, ec);
    std::lock_guard<std::mutex> lock(mu);
    Tally& y = tally[task.case_index];
    ++y.runs;
    y.seconds += r.seconds;
    if (r.verdict != Verdict::Passed) {
      ++y.failures;
      y.failed_messages.push_back("seed " + std::to_string(task.seed) + ": " + r.message);
    }
    const int d = ++done;
    if (d % 20 == 0 || d == int(tasks.size()))
      std::printf("calibrate: %d/%zu renders, %.0f s\n", d, tasks.size(), pt::seconds_since(t0));
    std::fflush(stdout);
  });

  std::ostringstream s;
  s << "# Calibration: false failures of the reference build\n\n"
    << "Each case was graded with the reference build at " << seeds << " seeds (" << first_seed << " to "
    << first_seed + uint64_t(seeds) - 1
    << "), none of them used to make the references. A deterministic case (normal shading at one sample per "
       "pixel) does not depend on the seed and was run once. Target: at most 1 % false failures per case.\n\n"
    << "Made by `grader calibrate --seeds " << seeds << "` at commit " << git_commit() << " on " << utc_now()
    << " (" << fmt_seconds(pt::seconds_since(t0)) << ").\n\n"
    << "The last column is the one-sided 95 % upper confidence bound on the case's false-failure rate "
       "(Clopper-Pearson): what the runs can vouch for. Pooled over the Monte Carlo cases the bound is "
       "much tighter (below the table).\n\n"
    << "| part | case | runs | false failures | rate | mean time (s) | 95 % bound |\n"
       "|---:|---|---:|---:|---:|---:|---:|\n";
  int total_runs = 0, total_failures = 0;
  for (size_t i = 0; i < cases.size(); ++i) {
    const Tally& y = tally[i];
    total_runs += y.runs;
    total_failures += y.failures;
    char rate[32], mean[32];
    std::snprintf(rate, sizeof rate, "%.1f %%", y.runs ? 100.0 * y.failures / y.runs : 0.0);
    std::snprintf(mean, sizeof mean, "%.2f", y.runs ? y.seconds / y.runs : 0.0);
    char bound[32];
    std::snprintf(bound, sizeof bound, "%.1f %%", 100.0 * rate_upper_bound(y.failures, y.runs));
    s << "| " << cases[i].part << " | " << cases[i].name << " | " << y.runs << (deterministic[i] ? " (deterministic)" : "")
      << " | " << y.failures << " | " << rate << " | " << mean << " | "
      << (deterministic[i] ? std::string("-") : std::string(bound)) << " |\n";
  }
  int mc_runs = 0, mc_failures = 0;
  for (size_t i = 0; i < cases.size(); ++i)
    if (!deterministic[i]) mc_runs += tally[i].runs, mc_failures += tally[i].failures;
  char pooled[200];
  std::snprintf(pooled, sizeof pooled,
                "Pooled over the Monte Carlo cases: %d false failures in %d renders, 95 %% upper bound %.2f %%.\n",
                mc_failures, mc_runs, 100.0 * rate_upper_bound(mc_failures, mc_runs));
  s << "\nIn all: " << total_failures << " false failures in " << total_runs << " graded renders. " << pooled;
  bool any = false;
  for (size_t i = 0; i < cases.size(); ++i)
    for (const std::string& m : tally[i].failed_messages) {
      if (!any) s << "\n## The failures\n\n";
      any = true;
      s << "- " << cases[i].name << ", " << m << "\n";
    }
  fs::create_directories(fs::path(table).parent_path());
  write_text(table, s.str());
  std::printf("%s", s.str().c_str());
  return total_failures ? kSomeFailed : kAllPassed;
}

// `path` as the user would type it from here: relative when it lies below
// the current folder.
std::string as_typed(const std::string& path) {
  std::error_code ec;
  const fs::path rel = fs::relative(path, fs::current_path(ec), ec);
  const std::string r = rel.string();
  return ec || r.empty() || r.rfind("..", 0) == 0 ? path : r;
}

int command_compare(const Common& common, bool list, const std::string& name, const std::string& file,
                    const std::string& out) {
  const std::vector<Case> cases = read_cases(common.cases);
  if (list) {
    print_case_commands(cases, as_typed(common.pathtracer), as_typed(common.scenes));
    return kAllPassed;
  }
  if (name.empty() || file.empty())
    throw std::runtime_error("compare: give a case and your render (grader compare CASE FILE), or --list");
  for (const Case& c : cases)
    if (c.name == name) return compare_render(c, common.references, file, out);
  throw std::runtime_error(common.cases + ": no case named '" + name + "' (grader compare --list shows them)");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"grader: scores a pathtracer build against the reference images"};
  app.require_subcommand(1);
  Common common;

  CLI::App* run = app.add_subcommand("run", "Grade a build: render every case, score, write the reports");
  common.add_to(run, true);
  std::string out = "grader_out";
  uint64_t seed = 1;
  bool quiet = false;
  run->add_option("-o,--out", out, "Output folder")->capture_default_str();
  run->add_option("--seed", seed, "Seed of the candidate's renders")->capture_default_str();
  run->add_flag("-q,--quiet", quiet, "No line per case while grading");

  CLI::App* make = app.add_subcommand("make-references", "Render the references with the reference build (slow)");
  common.add_to(make, true);
  int runs = 64;
  bool force = false;
  std::string work = "build/grader_work";
  make->add_option("--runs", runs, "Independent renders per case")->check(CLI::Range(2, 100000))->capture_default_str();
  make->add_flag("--force", force, "Remake references that already match their case");
  make->add_option("--work", work, "Scratch folder")->capture_default_str();
  int retime = 0;
  make->add_option("--retime", retime,
                   "Only re-measure the recorded render times: median of N renders, one at a time (-j ignored)")
      ->check(CLI::Range(1, 1000));

  CLI::App* calibrate = app.add_subcommand("calibrate", "Grade the reference build at many seeds: false-failure rates");
  common.add_to(calibrate, true);
  int seeds = 50;
  uint64_t first_seed = 2000;
  std::string table = std::string(PT_SOURCE_DIR) + "/grader/tables/calibration.md";
  calibrate->add_option("--seeds", seeds, "Seeds per case")->check(CLI::Range(1, 100000))->capture_default_str();
  calibrate->add_option("--first-seed", first_seed, "The first seed")->capture_default_str();
  calibrate->add_option("--table", table, "Where the table goes")->capture_default_str();
  calibrate->add_option("--work", work, "Scratch folder")->capture_default_str();

  CLI::App* compare = app.add_subcommand(
      "compare", "Compare your render of a case (PFM or PNG) with its reference; --list prints the cases' commands");
  std::string compare_case, compare_file, compare_out = ".";
  bool list = false;
  compare->add_option("case", compare_case, "The case your render is of (see --list)");
  compare->add_option("file", compare_file, "Your render: a .pfm (full statistics) or a .png (8-bit comparison)");
  compare->add_flag("--list", list, "Print every case with the command that renders it");
  compare->add_option("-o,--out", compare_out, "Where compare_CASE.png and .html go")->capture_default_str();
  compare->add_option("--cases", common.cases, "The case list")->capture_default_str();
  compare->add_option("--references", common.references, "The reference folder")->capture_default_str();
  compare->add_option("--scenes", common.scenes, "Where the cases' scenes are")->capture_default_str();

  CLI::App* merge = app.add_subcommand("merge", "Join the outputs of several shards into one set of reports");
  std::vector<std::string> shard_dirs;
  merge->add_option("-o,--out", out, "Output folder")->capture_default_str();
  merge->add_option("--cases", common.cases, "The case list (for the order)")->capture_default_str();
  merge->add_option("shards", shard_dirs, "Output folders of `grader run --shard`")->required();

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : kUsageError;
  }
  try {
    if (*run) return command_run(common, out, seed, quiet);
    if (*make) return command_make_references(common, runs, force, retime, work);
    if (*calibrate) return command_calibrate(common, seeds, first_seed, table, work + "/calibrate");
    if (*merge) return command_merge(common, out, shard_dirs);
    if (*compare) return command_compare(common, list, compare_case, compare_file, compare_out);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "grader: %s\n", e.what());
    return kUsageError;
  }
  return kUsageError;
}

