#include "tests/grader/grading_sandbox.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

extern char** environ;

namespace pt::test::grading {

namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using Catch::Matchers::EndsWith;
using Catch::Matchers::StartsWith;

double scale() {
  static const double s = pt::test::timeout_scale();
  return s;
}

std::string scale_arg(double s) {
  std::ostringstream o;
  o << s;
  return o.str();
}

std::string grader_exe() {
  const char* other = std::getenv("GRADER_UNDER_TEST");
  return other && *other ? other : GRADER_EXE;
}

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

int count_lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

JsonValue parse_json_file(const std::string& path) {
  INFO("file: " << path);
  REQUIRE(fs::exists(path));
  try {
    return StrictJson::parse(slurp(path));
  } catch (const std::exception& e) {
    FAIL(path << " is not valid JSON: " << e.what());
  }
  return {};
}

Run run_program(const std::vector<std::string>& argv, const std::vector<std::pair<std::string, std::string>>& env) {
  TempDir io;
  const std::string out_path = io.file("stdout"), err_path = io.file("stderr");
  std::vector<std::string> env_s;
  for (char** e = environ; *e; ++e)
    if (std::string(*e).rfind("FAKE_STUDENT_", 0) != 0) env_s.push_back(*e);
  for (const auto& [k, v] : env) env_s.push_back(k + "=" + v);
  std::vector<char*> args, envp;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  for (const std::string& e : env_s) envp.push_back(const_cast<char*>(e.c_str()));
  envp.push_back(nullptr);

  Run r;
  const unsigned limit = unsigned(std::ceil(kGraderTimeLimit * scale()));
  const pid_t pid = fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    const int in = open("/dev/null", O_RDONLY);
    const int out = open(out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err = open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (in < 0 || out < 0 || err < 0) _exit(126);
    dup2(in, 0);
    dup2(out, 1);
    dup2(err, 2);
    const struct rlimit as = {kGraderAddressSpace, kGraderAddressSpace};
    setrlimit(RLIMIT_AS, &as);
    alarm(limit);  // survives exec; SIGALRM ends the program
    execve(args[0], args.data(), envp.data());
    _exit(127);
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  r.finished = !(WIFSIGNALED(status) && WTERMSIG(status) == SIGALRM);
  if (WIFEXITED(status)) r.exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) r.signal = WTERMSIG(status);
  r.out = slurp(out_path);
  r.err = slurp(err_path);
  return r;
}

void check_finished(const Run& g, int code) {
  INFO(g.summary());
  REQUIRE(g.finished);   // else the grader hung and was killed after kGraderTimeLimit s (times the scale)
  CHECK(g.signal == 0);  // else the grader itself crashed
  CHECK(g.exit_code == code);
}

std::vector<Recorded> read_recorded(const std::string& path) {
  std::vector<Recorded> v;
  std::ifstream in(path);
  for (Recorded r; in >> r.pid >> r.start_time;) v.push_back(r);
  return v;
}

namespace {

// The recorded process as it is now: "" when gone (or the pid belongs to
// another process since), else its state letter (Z: a zombie, exited).
std::string state_of(const Recorded& r) {
  std::ifstream in("/proc/" + std::to_string(r.pid) + "/stat");
  if (!in) return "";
  const std::string stat((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const size_t paren = stat.rfind(')');
  if (paren == std::string::npos) return "";
  std::istringstream rest(stat.substr(paren + 2));
  std::string state, field;
  rest >> state;
  for (int i = 4; i <= 22 && (rest >> field); ++i) {
  }
  return field == r.start_time ? state : "";
}

}  // namespace

bool still_running(const Recorded& r) {
  const std::string state = state_of(r);
  return !state.empty() && state != "Z" && state != "X";
}

bool ends_within(const Recorded& r, int seconds) {
  const int fd = int(syscall(SYS_pidfd_open, r.pid, 0));
  if (fd < 0) return true;  // no such process
  bool ended = !still_running(r);  // checked after the pidfd pins the pid
  if (!ended) {
    struct pollfd p = {fd, POLLIN, 0};
    int n;
    while ((n = poll(&p, 1, seconds * 1000)) < 0 && errno == EINTR) {
    }
    ended = n == 1;
  }
  close(fd);
  return ended;
}

void kill_recorded(const std::string& path) {
  for (const Recorded& r : read_recorded(path))
    if (still_running(r)) kill(r.pid, SIGKILL);
}

// ---- The sandbox ----

// A case `name` (1 image, kPoints points) rendering `name`.dae, a copy of
// the project's CBempty.dae, at 16 x 12 with part 1.
void Sandbox::add_case(const std::string& name, double timeout, int part) {
  fs::copy_file(pt::test::project_scene("CBempty.dae"), scenes() + "/" + name + ".dae",
                fs::copy_options::overwrite_existing);
  std::ostringstream line;
  line << name << " " << part << " image " << kPoints << " " << timeout << " " << name << ".dae -r 16 12\n";
  lines_ += line.str();
  if (first_.empty()) first_ = name;
  pt::test::write_text(cases(), "# Robustness cases\n" + lines_);
}

// References for every case (or only `only`) with the real pathtracer.
void Sandbox::make_references(const std::string& only) {
  std::vector<std::string> argv = {grader_exe(), "make-references", "--pathtracer", PT_PATHTRACER_EXE, "--runs", "2",
                                   "-j", "2", "--references", refs(), "--cases", cases(), "--scenes", scenes(),
                                   "--work", path("work"), "--timeout-scale", scale_arg(scale())};
  if (!only.empty()) argv.insert(argv.end(), {"--case", only});
  const Run r = run_program(argv, {});
  INFO(r.summary());
  REQUIRE(r.finished);
  REQUIRE(r.exit_code == 0);
}

// `grader run` of the fake student in `fake_mode` into `out`, the cases'
// timeouts multiplied by `timeout_scale`.
Run Sandbox::grade(const std::string& fake_mode, const std::string& out, const std::vector<std::string>& extra,
                   double timeout_scale) const {
  std::vector<std::string> argv = {grader_exe(), "run", "--pathtracer", FAKE_STUDENT_EXE, "--cases", cases(),
                                   "--references", refs(), "--scenes", scenes(), "-o", out, "-j", "2",
                                   "--output-mb", "1", "--memory-mb", "512", "--timeout-scale",
                                   scale_arg(timeout_scale)};
  argv.insert(argv.end(), extra.begin(), extra.end());
  return run_program(argv, {{"FAKE_STUDENT_MODE", fake_mode},
                            {"FAKE_STUDENT_MEAN", refs() + "/" + first_ + "/mean.pfm"},
                            {"FAKE_STUDENT_PIDS", pids()}});
}

JsonValue check_reports(const std::string& out, const std::vector<std::string>& names, bool per_case) {
  const std::string txt = slurp(out + "/report.txt"), timing = slurp(out + "/timing.md"),
                    html = slurp(out + "/report.html");
  CHECK_THAT(txt, Contains("cases passed; score"));
  CHECK_THAT(timing, StartsWith("# Timing"));
  CHECK_THAT(html, StartsWith("<!DOCTYPE html>"));
  CHECK_THAT(html, EndsWith("</html>\n"));
  for (const std::string& n : names) {
    INFO("case " << n);
    CHECK_THAT(txt, Contains(" " + n + " "));
    CHECK_THAT(timing, Contains("| " + n + " |"));
    CHECK_THAT(html, Contains("id=\"" + n + "\""));
    if (per_case) CHECK(parse_json_file(out + "/cases/" + n + "/result.json").at("name").string == n);
  }
  const JsonValue results = parse_json_file(out + "/results.json");
  const auto& tests = results.at("tests").array;
  REQUIRE(tests.size() == names.size());
  double sum = 0;
  for (size_t i = 0; i < tests.size(); ++i) {
    CHECK_THAT(tests[i].at("name").string, StartsWith("Part ") && EndsWith(": " + names[i]));
    CHECK(tests[i].at("max_score").number == kPoints);
    sum += tests[i].at("score").number;
  }
  CHECK(results.at("score").number == Approx(sum));
  return results;
}

const JsonValue& test_named(const JsonValue& results, const std::string& name) {
  for (const JsonValue& t : results.at("tests").array)
    if (EndsWith(": " + name).match(t.at("name").string)) return t;
  FAIL("no test named " << name << " in results.json");
  throw std::logic_error("unreachable");
}

}  // namespace pt::test::grading
