#include "grader/src/commands.h"

#include <CLI/CLI.hpp>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <map>
#include <mutex>
#include <set>
#include <sstream>

#include "common/clock.h"
#include "grader/src/compare.h"
#include "grader/src/grade.h"
#include "grader/src/hints.h"
#include "common/image_io.h"
#include "grader/src/reports.h"
#include "grader/src/text.h"

namespace grader {
namespace cli {

namespace fs = std::filesystem;

std::string executable_dir() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string(".") : self.parent_path().string();
}

void Common::add_to(CLI::App* app, bool with_binary) {
  if (with_binary) app->add_option("--pathtracer", pathtracer, "The pathtracer binary to run")->capture_default_str();
  app->add_option("--cases", cases, "The case list")->capture_default_str();
  app->add_option("--references", references, "The reference folder")->capture_default_str();
  app->add_option("--scenes", scenes, "Where the cases' scenes are")->capture_default_str();
  app->add_option("--catalogue", catalogue, "The known bugs' signatures, for the report's hints")->capture_default_str();
  app->add_option("--part", parts, "Only these parts (repeatable)")->check(CLI::Range(1, 9));
  app->add_option("--case", names, "Only these cases (repeatable)");
  app->add_option("--shard", shard, "K/N: only the K-th of N equal slices of the cases (K = 1..N)");
  app->add_option("-j,--jobs", jobs, "Cases (or renders) at a time")->check(CLI::Range(1, 256))->capture_default_str();
  app->add_option("-t,--threads", threads, "Threads per render (-t)")->check(CLI::Range(1, 256))->capture_default_str();
  app->add_option("--timeout-scale", timeout_scale, "Multiply every case's timeout (slow machines)")
      ->check(CLI::Range(0.01, 1000.0))->capture_default_str();
  app->add_option("--memory-mb", memory_mb, "Address-space limit per render")->check(CLI::Range(64, 1 << 20))->capture_default_str();
  app->add_option("--output-mb", output_mb, "Output-size limit per render")->check(CLI::Range(1, 1 << 20))->capture_default_str();
  app->add_option("--hidden-cases", hidden_cases, "A second case list, graded after --cases and shown without names");
  app->add_option("--hidden-references", hidden_references,
                  "The hidden cases' references (default: references/ beside --hidden-cases)");
}

void Common::add_sandbox_to(CLI::App* app) {
  app->add_option("--sandbox", sandbox, "Where renders run: none, bwrap (bubblewrap namespaces) or user (an account alone)")
      ->check(CLI::IsMember({"none", "bwrap", "user"}))
      ->capture_default_str();
  app->add_option("--sandbox-user", sandbox_users,
                  "Unprivileged accounts to render as, one per job (comma-separated; needed as root)");
  app->add_option("--sandbox-tmp", sandbox_tmp, "Where each render's staging folder is made")->capture_default_str();
}

RunSettings Common::run_settings() const {
  RunSettings s;
  s.pathtracer = pathtracer;
  s.scenes_dir = scenes;
  s.threads = threads;
  s.timeout_scale = timeout_scale;
  s.memory_bytes = uint64_t(memory_mb) << 20;
  s.output_bytes = uint64_t(output_mb) << 20;
  parse_sandbox_mode(sandbox, &s.sandbox.mode);
  if (s.sandbox.on()) s.sandbox.accounts = lookup_accounts(sandbox_users);
  s.sandbox.root = sandbox_tmp;
  return s;
}

std::string Common::hidden_reference_root() const {
  if (!hidden_references.empty()) return hidden_references;
  return (fs::absolute(fs::path(hidden_cases)).parent_path() / "references").string();
}

std::string Common::references_for(const Case& c) const { return c.hidden ? hidden_reference_root() : references; }

std::vector<Case> Common::all_cases() const {
  std::vector<Case> all = read_cases(cases);
  if (hidden_cases.empty()) return all;
  std::set<std::string> names;
  for (const Case& c : all) names.insert(c.name);
  for (Case c : read_cases(hidden_cases)) {
    if (!names.insert(c.name).second)
      throw std::runtime_error(hidden_cases + ":" + std::to_string(c.line) + ": case " + c.name +
                               " is in " + cases + " too");
    c.hidden = true;
    all.push_back(c);
  }
  return all;
}

Rules Common::rules() const {
  std::vector<Case> shown, hidden;
  for (const Case& c : all_cases()) (c.hidden ? hidden : shown).push_back(c);
  return make_rules(shown, references, hidden, hidden_cases.empty() ? "" : hidden_reference_root());
}

std::vector<Case> Common::select() const {
  std::vector<Case> all = all_cases();
  std::set<std::string> known;
  for (const Case& c : all) known.insert(c.name);
  for (const std::string& n : names)
    if (!known.count(n))
      throw std::runtime_error(cases + (hidden_cases.empty() ? "" : " and " + hidden_cases) + ": no case named '" + n + "'");
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

void Common::check_binary() const {
  // access() alone accepts a directory (X_OK is search permission there).
  std::error_code ec;
  if (!fs::is_regular_file(pathtracer, ec) || access(pathtracer.c_str(), X_OK) != 0)
    throw std::runtime_error(pathtracer + ": not an executable file");
}

int exit_code_for(const std::vector<CaseResult>& results) {
  int code = kAllPassed;
  for (const auto& r : results) {
    if (r.verdict == Verdict::Error) return kUsageError;
    if (r.verdict == Verdict::Failed) code = kSomeFailed;
  }
  return code;
}

std::string git_commit() {
  FILE* p = popen(("git -C '" + source_dir() + "' rev-parse --short HEAD 2>/dev/null").c_str(), "r");
  if (!p) return "unknown";
  char buf[64] = {0};
  const bool ok = std::fgets(buf, sizeof buf, p) != nullptr;
  pclose(p);
  std::string s = ok ? buf : "unknown";
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r')) s.pop_back();
  return s;
}

int command_run(const Common& common, const std::string& out, uint64_t seed, bool quiet) {
  const auto t0 = pt::Clock::now();
  const std::string started = utc_now();
  const std::vector<Case> cases = common.select();
  common.check_binary();
  fs::create_directories(out + "/cases");
  const RunSettings run = common.run_settings();
  if (run.sandbox.on()) {
    // Renders run as other accounts: the output folder must hide the other
    // cases' renders and the reports from them (and from the world).
    if (geteuid() == 0 && chmod(out.c_str(), 0700) != 0)
      throw std::runtime_error(out + ": cannot make it readable by root only");
    std::vector<std::string> secrets = {common.cases, common.references, fs::absolute(out).string(),
                                        executable_dir() + "/grader"};
    if (!common.hidden_cases.empty()) secrets.insert(secrets.end(), {common.hidden_cases, common.hidden_reference_root()});
    check_sandbox(run.sandbox, common.jobs, secrets);
    lock_accounts(run.sandbox, fs::is_directory("/run/lock") ? "/run/lock" : run.sandbox.root);
    if (!common.hidden_cases.empty())
      check_no_copies(run.sandbox, {fs::path(common.hidden_cases).parent_path().string(), common.hidden_reference_root()});
  }
  std::vector<CaseResult> results(cases.size());
  std::mutex mu;
  int done = 0;
  const Rules rules = common.rules();
  parallel_for(int(cases.size()), common.jobs, [&](int i) {
    const Case& c = cases[size_t(i)];
    const std::string dir = out + "/cases/" + c.name;
    CaseResult r;
    try {
      r = grade_case(run, common.references_for(c), c, seed, dir, rules);
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
  info.hints = run_hints(common, results, &run, out);
  write_reports(out, results, info);
  std::printf("\n%s", terminal_table(results, info.hints).c_str());
  std::printf("Reports: %s/{report.txt,timing.md,results.json,report.html} (%.0f s)\n", out.c_str(),
              info.wall_seconds);
  return exit_code_for(results);
}

Catalogue hint_catalogue(const Common& common) {
  std::error_code ec;
  if (!fs::is_regular_file(common.catalogue, ec)) return {};
  try {
    return read_catalogue(common.catalogue);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "grader: no hints: %s\n", e.what());
    return {};
  }
}

std::vector<std::string> run_hints(const Common& common, const std::vector<CaseResult>& results,
                                   const RunSettings* run, const std::string& out) {
  const Catalogue catalogue = hint_catalogue(common);
  if (catalogue.bugs.empty()) return {};
  try {
    const CaseGroups groups = case_groups(read_cases(common.cases));
    // The function checks, when the build lost points somewhere (a build
    // that passes everything gets no hints) and the references have them:
    // run now (grader run), or read from the graded folder (grader merge).
    const bool lost = std::any_of(results.begin(), results.end(), [](const CaseResult& r) {
      return r.verdict != Verdict::Passed || r.score < r.max_score;
    });
    std::error_code ec;
    ProbeVerdicts probes;
    if (lost && !out.empty() && fs::is_regular_file(reference_probes_path(common.references), ec)) {
      int max_part = 1;
      for (const CaseResult& r : results) max_part = std::max(max_part, r.c.part);
      std::string failure;
      if (run && !run_probes(*run, max_part, out + "/probes", &failure))
        std::fprintf(stderr, "grader: the function checks did not run: %s\n", failure.c_str());
      probes = probe_verdicts_for_folder(out, common.references);
    }
    return hint_lines(results, catalogue, groups, &probes);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "grader: no hints: %s\n", e.what());
    return {};
  }
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
  // The function checks of the first shard that ran them.
  std::string probed;
  for (const std::string& d : shard_dirs)
    if (probed.empty() && fs::is_regular_file(d + "/probes/probes.json")) probed = d;
  if (!probed.empty() && fs::absolute(probed) != fs::absolute(out)) {
    fs::create_directories(out + "/probes");
    fs::copy_file(probed + "/probes/probes.json", out + "/probes/probes.json", fs::copy_options::overwrite_existing);
  }
  info.hints = run_hints(common, results, nullptr, probed.empty() ? "" : out);
  write_reports(out, results, info);
  std::printf("%s", terminal_table(results, info.hints).c_str());
  return exit_code_for(results);
}

namespace {

// `path` as the user would type it from here: relative when it lies below
// the current folder.
std::string as_typed(const std::string& path) {
  std::error_code ec;
  const fs::path rel = fs::relative(path, fs::current_path(ec), ec);
  const std::string r = rel.string();
  return ec || r.empty() || r.rfind("..", 0) == 0 ? path : r;
}

}  // namespace

int command_compare(const Common& common, bool list, const std::string& name, const std::vector<std::string>& files,
                    const std::string& out) {
  const std::vector<Case> cases = read_cases(common.cases);
  if (list) {
    print_case_commands(cases, as_typed(common.pathtracer), as_typed(common.scenes));
    return kAllPassed;
  }
  if (name.empty() || files.empty())
    throw std::runtime_error("compare: give a case and your render (grader compare CASE FILE), or --list");
  for (const Case& c : cases)
    if (c.name == name)
      return compare_render(c, common.references, files, out, make_rules(cases, common.references),
                            hint_catalogue(common), case_groups(cases));
  throw std::runtime_error(common.cases + ": no case named '" + name + "' (grader compare --list shows them)");
}

}  // namespace cli
}  // namespace grader
