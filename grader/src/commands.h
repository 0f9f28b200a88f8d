// The grader's commands (`grader run`, `merge`, `compare`,
// `make-references`, `calibrate`) and the options they share; main.cpp
// parses the command line and calls one of them.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <string>
#include <thread>
#include <vector>

#include "grader/src/case_list.h"
#include "grader/src/case_result.h"
#include "grader/src/hints.h"
#include "grader/src/rules.h"
#include "grader/src/run_case.h"
#include "grader/src/sandbox.h"

// CLI11 is included only where the command line is built (main.cpp and
// commands.cpp): it is the slowest header of the grader to compile.
namespace CLI {
class App;
}

namespace grader {
namespace cli {

// Exit codes.
constexpr int kAllPassed = 0, kSomeFailed = 1, kUsageError = 2;

// The folder the running grader's binary is in.
std::string executable_dir();

// The source tree the grader was built from (its default case list,
// references and scenes); defined in source_dir.cpp, the one file that
// needs the tree's path at compile time.
std::string source_dir();

// The options every command shares.
struct Common {
  std::string pathtracer = executable_dir() + "/pathtracer";
  std::string cases = source_dir() + "/grader/cases.txt";
  std::string references = source_dir() + "/reference_images";
  std::string scenes = source_dir() + "/scenes";
  std::string catalogue = source_dir() + "/grader/known_bugs.json";
  std::vector<int> parts;
  std::vector<std::string> names;
  std::string shard;  // "K/N"
  int jobs = 2;
  int threads = 1;
  double timeout_scale = 1.0;
  int memory_mb = 4096;
  int output_mb = 256;
  // Hidden cases (the Gradescope package's): graded after the case list's,
  // shown to students without names or settings.
  std::string hidden_cases;
  std::string hidden_references;  // default: `references/` beside hidden_cases
  // Where renders run (sandbox.h).
  std::string sandbox = "none";
  std::vector<std::string> sandbox_users;
  std::string sandbox_tmp = "/tmp";

  void add_to(CLI::App* app, bool with_binary);
  // --sandbox, --sandbox-user, --sandbox-tmp (grader run only).
  void add_sandbox_to(CLI::App* app);
  RunSettings run_settings() const;
  // The selected cases (the hidden ones last, marked hidden). Throws
  // std::runtime_error on a bad file or filter.
  std::vector<Case> select() const;
  // Every case of the case list and of the hidden list, whatever a run
  // selects.
  std::vector<Case> all_cases() const;
  // The reference folder of a case.
  std::string references_for(const Case& c) const;
  // The hidden references' folder.
  std::string hidden_reference_root() const;
  // The grading rules for all_cases().
  Rules rules() const;
  // Throws std::runtime_error when --pathtracer is not an executable file.
  void check_binary() const;
};

// Runs `task(i)` for i in [0, n) on `jobs` threads.
// Each thread is a job slot (set_job_slot): a sandboxed render runs as
// its slot's account.
template <class F>
void parallel_for(int n, int jobs, F task) {
  std::atomic<int> next{0};
  std::vector<std::thread> pool;
  for (int j = 0; j < std::max(1, std::min(jobs, n)); ++j)
    pool.emplace_back([&, j] {
      set_job_slot(j);
      for (int i; (i = next.fetch_add(1)) < n;) task(i);
    });
  for (auto& t : pool) t.join();
}

// The exit code of `run` and `merge` for these results.
int exit_code_for(const std::vector<CaseResult>& results);

// The source tree's short commit, or "unknown".
std::string git_commit();

int command_run(const Common& common, const std::string& out, uint64_t seed, bool quiet);
// The report's hint lines for these results (none when the catalogue is
// missing: hints are a help, not a verdict), then the function checks'
// that disagree. The checks (probes.h) run when the build lost points and
// the references have the reference's answers: with `run`, the build is
// checked now into out/probes/; without it, out/probes/ is read as it is
// (empty `out`: no checks).
// `grader functions`: the build's function checks (`pathtracer --probe`,
// parts 1 to max_part) against the reference's, a line per function; into
// `out`. Exit status kAllPassed when every function agrees.
int command_functions(const Common& common, int max_part, const std::string& out);
std::vector<std::string> run_hints(const Common& common, const std::vector<CaseResult>& results,
                                   const RunSettings* run, const std::string& out);
// The known bugs of --catalogue; empty (with a line on stderr when it is
// malformed) when it cannot be read.
Catalogue hint_catalogue(const Common& common);
// `grader hints`: the tables of tables/hints.md (each known bug left out,
// each function's bugs left out), or with graded folders, their hints.
int command_hints(const Common& common, const std::string& table, const std::vector<std::string>& graded);
// Rewrites each graded folder's cases/<case>/result.json into
// out/<folder name>/ with the image figures of its signature made again
// from its kept renders; nothing else changes.
int command_rescore(const Common& common, const std::vector<std::string>& grade_dirs, const std::string& out);
int command_merge(const Common& common, const std::string& out, const std::vector<std::string>& shard_dirs);
int command_compare(const Common& common, bool list, const std::string& name, const std::vector<std::string>& files,
                    const std::string& out);
int command_make_references(const Common& common, int runs, bool force, int retime, bool costs_only,
                            const std::string& work);
// A build to calibrate: a name for the table and its pathtracer.
struct Build {
  std::string name, pathtracer;
};
int command_calibrate(const Common& common, const std::vector<Build>& extra_builds, int seeds, uint64_t first_seed,
                      const std::string& table, const std::string& work);

}  // namespace cli
}  // namespace grader
