// grader calibrate: grades the reference build at seeds never used for the
// references and writes the table of false failures.
#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <mutex>
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

// One graded render: a case at a seed.
struct Task {
  size_t case_index;
  uint64_t seed;
};

// What the renders of one case found.
struct Tally {
  int runs = 0, failures = 0;
  double worst_relmse_ratio = 0, seconds = 0;
  std::vector<std::string> failed_messages;
};

// The renders to grade, and which cases are deterministic. Throws when a
// case has no usable reference.
std::vector<Task> calibration_tasks(const Common& common, const std::vector<Case>& cases, int seeds,
                                    uint64_t first_seed, std::vector<bool>* deterministic) {
  std::vector<Task> tasks;
  deterministic->assign(cases.size(), false);
  for (size_t i = 0; i < cases.size(); ++i) {
    Reference ref;
    std::string why;
    if (!load_reference(common.references, cases[i], &ref, &why)) throw std::runtime_error(cases[i].name + ": " + why);
    (*deterministic)[i] = ref.deterministic;
    // A deterministic image does not depend on the seed: one run says it all.
    const int n = ref.deterministic ? 1 : seeds;
    for (int s = 0; s < n; ++s) tasks.push_back({i, first_seed + uint64_t(s)});
  }
  return tasks;
}

// Grades every task, common.jobs at a time, printing progress every 20.
std::vector<Tally> grade_tasks(const Common& common, const std::vector<Case>& cases, const std::vector<Task>& tasks,
                               const std::string& work, pt::Clock::time_point t0) {
  std::vector<Tally> tally(cases.size());
  std::mutex mu;
  std::atomic<int> done{0};
  const RunSettings run = common.run_settings();
  const Rules rules = make_rules(read_cases(common.cases), common.references);
  parallel_for(int(tasks.size()), common.jobs, [&](int t) {
    const Task& task = tasks[size_t(t)];
    const Case& c = cases[task.case_index];
    const std::string dir = work + "/" + c.name + "_" + std::to_string(task.seed);
    CaseResult r = grade_case(run, common.references, c, task.seed, dir, rules);
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
  return tally;
}

void write_table_header(std::ostringstream& s, int seeds, uint64_t first_seed, pt::Clock::time_point t0) {
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
}

void write_table_row(std::ostringstream& s, const Case& c, const Tally& y, bool deterministic) {
  char rate[32], mean[32];
  std::snprintf(rate, sizeof rate, "%.1f %%", y.runs ? 100.0 * y.failures / y.runs : 0.0);
  std::snprintf(mean, sizeof mean, "%.2f", y.runs ? y.seconds / y.runs : 0.0);
  char bound[32];
  std::snprintf(bound, sizeof bound, "%.1f %%", 100.0 * rate_upper_bound(y.failures, y.runs));
  s << "| " << c.part << " | " << c.name << " | " << y.runs << (deterministic ? " (deterministic)" : "")
    << " | " << y.failures << " | " << rate << " | " << mean << " | "
    << (deterministic ? std::string("-") : std::string(bound)) << " |\n";
}

// The totals, the bound pooled over the Monte Carlo cases (a deterministic
// case's runs say nothing about the rate), and every failure's message.
void write_table_summary(std::ostringstream& s, const std::vector<Case>& cases, const std::vector<bool>& deterministic,
                         const std::vector<Tally>& tally) {
  int total_runs = 0, total_failures = 0, mc_runs = 0, mc_failures = 0;
  for (size_t i = 0; i < cases.size(); ++i) {
    total_runs += tally[i].runs;
    total_failures += tally[i].failures;
    if (!deterministic[i]) mc_runs += tally[i].runs, mc_failures += tally[i].failures;
  }
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
}

}  // namespace

int command_calibrate(const Common& common, int seeds, uint64_t first_seed, const std::string& table,
                      const std::string& work) {
  const std::vector<Case> cases = common.select();
  common.check_binary();
  std::vector<bool> deterministic;
  const std::vector<Task> tasks = calibration_tasks(common, cases, seeds, first_seed, &deterministic);
  const auto t0 = pt::Clock::now();
  const std::vector<Tally> tally = grade_tasks(common, cases, tasks, work, t0);

  std::ostringstream s;
  write_table_header(s, seeds, first_seed, t0);
  int total_failures = 0;
  for (size_t i = 0; i < cases.size(); ++i) {
    write_table_row(s, cases[i], tally[i], deterministic[i]);
    total_failures += tally[i].failures;
  }
  write_table_summary(s, cases, deterministic, tally);
  fs::create_directories(fs::path(table).parent_path());
  write_text(table, s.str());
  std::printf("%s", s.str().c_str());
  return total_failures ? kSomeFailed : kAllPassed;
}

}  // namespace cli
}  // namespace grader
