// grader calibrate: grades correct builds (the reference's, and the legal
// variants' builds given with --build) at seeds never used for the
// references, and writes the table of false failures: per whole grading
// run (every case at one seed) and per case, with the image-mean test's z
// spread, which says whether the tests' levels are what they claim.
#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <set>
#include <sstream>

#include "common/clock.h"
#include "grader/src/commands.h"
#include "grader/src/grade.h"
#include "grader/src/reference.h"
#include "grader/src/text.h"

namespace grader {
namespace cli {

namespace fs = std::filesystem;

namespace {

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

// One graded case: a build, a case, a seed.
struct Task {
  size_t build, case_index;
  uint64_t seed;
};

// What the renders of one case by one build found.
struct Tally {
  int runs = 0, failures = 0;
  double seconds = 0;
  double z_sum = 0, z_sum2 = 0;  // the image-mean test's z, every channel
  int z_count = 0;
  std::set<uint64_t> failed_seeds;
  std::vector<std::string> failed_messages;
  double z_sd() const {
    if (z_count < 2) return -1;
    const double m = z_sum / z_count;
    return std::sqrt(std::max(0.0, (z_sum2 - z_count * m * m) / (z_count - 1)));
  }
};

// The renders to grade, and which cases are deterministic (graded once:
// their image does not depend on the seed). Throws when a case has no
// usable reference.
std::vector<Task> calibration_tasks(const Common& common, const std::vector<Case>& cases, size_t builds, int seeds,
                                    uint64_t first_seed, std::vector<bool>* deterministic) {
  std::vector<Task> tasks;
  deterministic->assign(cases.size(), false);
  for (size_t i = 0; i < cases.size(); ++i) {
    Reference ref;
    std::string why;
    if (!load_reference(common.references, cases[i], &ref, &why)) throw std::runtime_error(cases[i].name + ": " + why);
    (*deterministic)[i] = ref.deterministic;
  }
  for (size_t b = 0; b < builds; ++b)
    for (int s = 0; s < seeds; ++s)
      for (size_t i = 0; i < cases.size(); ++i)
        if (!(*deterministic)[i] || s == 0) tasks.push_back({b, i, first_seed + uint64_t(s)});
  return tasks;
}

// Grades every task, common.jobs at a time, printing progress every 20.
std::vector<std::vector<Tally>> grade_tasks(const Common& common, const std::vector<Build>& builds,
                                            const std::vector<Case>& cases, const std::vector<Task>& tasks,
                                            const std::string& work, pt::Clock::time_point t0) {
  std::vector<std::vector<Tally>> tally(builds.size(), std::vector<Tally>(cases.size()));
  std::mutex mu;
  std::atomic<int> done{0};
  const Rules rules = make_rules(read_cases(common.cases), common.references);
  parallel_for(int(tasks.size()), common.jobs, [&](int t) {
    const Task& task = tasks[size_t(t)];
    const Case& c = cases[task.case_index];
    RunSettings run = common.run_settings();
    run.pathtracer = builds[task.build].pathtracer;
    const std::string dir = work + "/" + builds[task.build].name + "_" + c.name + "_" + std::to_string(task.seed);
    const CaseResult r = grade_case(run, common.references, c, task.seed, dir, rules);
    std::error_code ec;
    fs::remove_all(dir, ec);
    std::lock_guard<std::mutex> lock(mu);
    Tally& y = tally[task.build][task.case_index];
    ++y.runs;
    y.seconds += r.seconds;
    for (int ch = 0; ch < 3; ++ch) {
      const auto z = r.signature.find("mean_z_" + std::to_string(ch));
      if (z == r.signature.end()) continue;
      y.z_sum += z->second;
      y.z_sum2 += z->second * z->second;
      ++y.z_count;
    }
    if (r.verdict != Verdict::Passed || r.score < r.max_score) {
      ++y.failures;
      y.failed_seeds.insert(task.seed);
      y.failed_messages.push_back("seed " + std::to_string(task.seed) + ": " + r.message);
    }
    const int d = ++done;
    if (d % 20 == 0 || d == int(tasks.size()))
      std::printf("calibrate: %d/%zu graded cases, %.0f s\n", d, tasks.size(), pt::seconds_since(t0));
    std::fflush(stdout);
  });
  return tally;
}

// Whole runs: every case at one seed. A failing deterministic case
// (graded once) fails every run of its build.
struct RunCount {
  int runs = 0, failed = 0;
};

RunCount whole_runs(const std::vector<Tally>& tally, const std::vector<bool>& deterministic, int seeds) {
  std::set<uint64_t> failed;
  bool always = false;
  for (size_t i = 0; i < tally.size(); ++i) {
    if (deterministic[i] && tally[i].failures > 0) always = true;
    failed.insert(tally[i].failed_seeds.begin(), tally[i].failed_seeds.end());
  }
  return RunCount{seeds, always ? seeds : int(failed.size())};
}

std::string pct(double x) { return fmt("%.2f %%", 100.0 * x); }

void write_table(std::ostringstream& s, const Common& common, const std::vector<Build>& builds,
                 const std::vector<Case>& cases, const std::vector<bool>& deterministic,
                 const std::vector<std::vector<Tally>>& tally, int seeds, uint64_t first_seed,
                 pt::Clock::time_point t0) {
  const Rules rules = make_rules(read_cases(common.cases), common.references);
  s << "<!-- REFERENCE ONLY: measured on the reference and its legal variants; the starter kit leaves this table out -->\n"
    << "# Calibration: false failures of correct builds\n\n"
    << "Each build was graded on every case at " << seeds << " seeds (" << first_seed << " to "
    << first_seed + uint64_t(seeds) - 1
    << "), none of them used to make the references; a deterministic case (normal shading at one sample per "
       "pixel) does not depend on the seed and was graded once per build. A case fails falsely when a correct "
       "build loses any point on it. Every build here is correct: the reference's and the legal variants' "
       "(instructors/legal_variants/).\n\n"
    << "Goal: at most 0.1 % of whole grading runs (every case at one seed) lose a point anywhere. The grader "
       "shares that budget among the "
    << rules.scored_images << " Monte Carlo images a run scores (" << fmt("%.2g", rules.image_alpha())
    << " each, half to the block test, half to the image-mean test; the per-pixel test is bounded by its "
       "allowance instead).\n\n"
    << "Made by `grader calibrate --seeds " << seeds;
  for (size_t b = 1; b < builds.size(); ++b) s << " --build " << builds[b].name << "=...";
  s << "` at commit " << git_commit() << " on " << utc_now() << " (" << fmt_seconds(pt::seconds_since(t0))
    << ").\n\n## Whole runs\n\n"
    << "| build | runs | runs with a false failure | rate | 95 % upper bound |\n|---|---:|---:|---:|---:|\n";
  int all_runs = 0, all_failed = 0;
  for (size_t b = 0; b < builds.size(); ++b) {
    const RunCount rc = whole_runs(tally[b], deterministic, seeds);
    all_runs += rc.runs;
    all_failed += rc.failed;
    s << "| " << builds[b].name << " | " << rc.runs << " | " << rc.failed << " | "
      << pct(rc.runs ? double(rc.failed) / rc.runs : 0.0) << " | " << pct(rate_upper_bound(rc.failed, rc.runs))
      << " |\n";
  }
  s << "| **all builds** | " << all_runs << " | " << all_failed << " | "
    << pct(all_runs ? double(all_failed) / all_runs : 0.0) << " | " << pct(rate_upper_bound(all_failed, all_runs))
    << " |\n\nThe 95 % bound is one-sided (Clopper-Pearson): what the runs can vouch for.\n\n## Per case\n\n"
    << "Failures per build, and the spread (standard deviation) of the image-mean test's z over the "
       "reference build's renders and channels: 1 when the variance the test divides by is the true one, less "
       "when it is conservative; a spread well above 1 would mean the test's level is not what it claims.\n\n"
    << "| part | case |";
  for (const Build& b : builds) s << " " << b.name << " |";
  s << " z spread |\n|---:|---|";
  for (size_t b = 0; b < builds.size(); ++b) s << "---:|";
  s << "---:|\n";
  for (size_t i = 0; i < cases.size(); ++i) {
    s << "| " << cases[i].part << " | " << cases[i].name << (deterministic[i] ? " (deterministic)" : "") << " |";
    for (size_t b = 0; b < builds.size(); ++b)
      s << " " << tally[b][i].failures << "/" << tally[b][i].runs << " |";
    const double sd = tally[0][i].z_sd();
    s << " " << (sd < 0 ? std::string("-") : fmt("%.2f", sd)) << " |\n";
  }
  bool any = false;
  for (size_t b = 0; b < builds.size(); ++b)
    for (size_t i = 0; i < cases.size(); ++i)
      for (const std::string& m : tally[b][i].failed_messages) {
        if (!any) s << "\n## The failures\n\n";
        any = true;
        s << "- " << builds[b].name << ", " << cases[i].name << ", " << m << "\n";
      }
}

}  // namespace

int command_calibrate(const Common& common, const std::vector<Build>& extra_builds, int seeds, uint64_t first_seed,
                      const std::string& table, const std::string& work) {
  const std::vector<Case> cases = common.select();
  common.check_binary();
  std::vector<Build> builds = {{"reference", common.pathtracer}};
  for (const Build& b : extra_builds) {
    std::error_code ec;
    if (!fs::is_regular_file(b.pathtracer, ec)) throw std::runtime_error(b.pathtracer + ": not an executable file");
    builds.push_back(b);
  }
  std::vector<bool> deterministic;
  const std::vector<Task> tasks = calibration_tasks(common, cases, builds.size(), seeds, first_seed, &deterministic);
  const auto t0 = pt::Clock::now();
  const auto tally = grade_tasks(common, builds, cases, tasks, work, t0);

  std::ostringstream s;
  write_table(s, common, builds, cases, deterministic, tally, seeds, first_seed, t0);
  fs::create_directories(fs::path(table).parent_path());
  write_text(table, s.str());
  std::printf("%s", s.str().c_str());
  int failures = 0;
  for (const auto& per_build : tally)
    for (const Tally& y : per_build) failures += y.failures;
  return failures ? kSomeFailed : kAllPassed;
}

}  // namespace cli
}  // namespace grader
