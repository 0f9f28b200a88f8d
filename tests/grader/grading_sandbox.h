// What the grader's robustness tests (test_grader_robustness.cpp) share:
// running a program under a time limit, the processes the fake student
// records, a grading sandbox (scenes, case list, references with the real
// pathtracer) and the checks of a finished run's reports.
//
// Every time limit here is multiplied by PT_TEST_TIMEOUT_SCALE (README,
// "Tests"); they only bound a failing run: a passing one ends as soon as
// what it checks happens.
#pragma once
#include <sys/resource.h>
#include <sys/types.h>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "tests/grader/strict_json.h"
#include "tests/support.h"

namespace pt::test::grading {

constexpr double kPoints = 2;            // every test case is worth 2 points
constexpr int kGraderTimeLimit = 120;    // s: a grader still running then has hung
constexpr int kProcessEndLimit = 30;     // s: a killed process still there then has survived
constexpr rlim_t kGraderAddressSpace = rlim_t(2) << 30;  // a memory bomb fails instead of swapping

// The scale of every timeout (tests/support.h), as the grader's --timeout-scale.
double scale();
std::string scale_arg(double s);

// The grader under test: GRADER_UNDER_TEST when set, else this build's.
std::string grader_exe();

std::string slurp(const std::string& path);
int count_lines(const std::string& s);
JsonValue parse_json_file(const std::string& path);

// ---- Running programs ----

struct Run {
  bool finished = false;  // false: killed at kGraderTimeLimit times the scale (it hung)
  int exit_code = -1;     // when it exited
  int signal = 0;         // when a signal ended it
  std::string out, err;
  std::string summary() const {
    const auto cut = [](const std::string& s) { return s.size() > 3000 ? s.substr(0, 3000) + "..." : s; };
    return "exit " + std::to_string(exit_code) + ", signal " + std::to_string(signal) + "\n[stdout]\n" + cut(out) +
           "\n[stderr]\n" + cut(err);
  }
};

// Runs argv (no shell) with `env` added to this process's environment, under
// an address-space limit and an alarm that ends it after kGraderTimeLimit
// times the scale.
Run run_program(const std::vector<std::string>& argv, const std::vector<std::pair<std::string, std::string>>& env);

// The grader ran to its end, by itself, with `code`.
void check_finished(const Run& g, int code);

// ---- Processes the fake student leaves behind ----

struct Recorded {
  pid_t pid = 0;
  std::string start_time;  // field 22 of /proc/<pid>/stat
};

std::vector<Recorded> read_recorded(const std::string& path);
bool still_running(const Recorded& r);

// True when the recorded process has ended, or ends within `seconds` (the
// grader's SIGKILL is queued when it returns, but a process dies on its own
// schedule): waits on a pidfd, which is readable once the process exits.
bool ends_within(const Recorded& r, int seconds);

// Kills whatever the fake student recorded in `path` and is still running.
void kill_recorded(const std::string& path);

// Kills, at the end of a test, whatever the fake student recorded and is
// still running (only when a check has already failed), so that a failing
// test leaves nothing behind.
class KillLeftovers {
 public:
  explicit KillLeftovers(std::string path) : path_(std::move(path)) {}
  ~KillLeftovers() { kill_recorded(path_); }

 private:
  std::string path_;
};

// ---- A grading sandbox: scenes, case list, references ----

class Sandbox {
 public:
  Sandbox() : leftovers_(pids()) { std::filesystem::create_directories(scenes()); }

  std::string path(const std::string& name) const { return tmp_.file(name); }
  std::string scenes() const { return path("scenes"); }
  std::string cases() const { return path("cases.txt"); }
  std::string refs() const { return path("refs"); }
  std::string pids() const { return path("pids.txt"); }

  // A case `name` (1 image, kPoints points) rendering `name`.dae, a copy of
  // the project's CBempty.dae, at 16 x 12 with part 1.
  void add_case(const std::string& name, double timeout, int part = 1);

  // References for every case (or only `only`) with the real pathtracer.
  void make_references(const std::string& only = "");

  // `grader run` of the fake student in `fake_mode` into `out`, the cases'
  // timeouts multiplied by `timeout_scale`.
  Run grade(const std::string& fake_mode, const std::string& out, const std::vector<std::string>& extra = {},
            double timeout_scale = scale()) const;

 private:
  TempDir tmp_;
  KillLeftovers leftovers_;
  std::string lines_, first_;
};

// Every report of a finished run is there and complete, with `names` in this
// order; returns results.json (Gradescope's format, checked strictly).
// `per_case`: the cases' own result.json too (`run` writes them, `merge`
// reads them from the shards).
JsonValue check_reports(const std::string& out, const std::vector<std::string>& names, bool per_case = true);

const JsonValue& test_named(const JsonValue& results, const std::string& name);

}  // namespace pt::test::grading
