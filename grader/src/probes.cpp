#include "grader/src/probes.h"

#include <cmath>
#include <filesystem>

#include "grader/src/child_process.h"
#include "grader/src/sandbox.h"
#include "grader/src/text.h"

namespace grader {

namespace fs = std::filesystem;

namespace {

// The build's file is a student's program's output: at most this large.
constexpr uint64_t kMaxProbeBytes = 8ull << 20;

const pt::Json* member_array(const pt::Json& j, const char* key) {
  const pt::Json* a = j.get(key);
  return a && a->type == pt::Json::Type::Array ? a : nullptr;
}

// name -> the function's entry ("function", "part", "status", "checks").
std::map<std::string, const pt::Json*> by_function(const pt::Json& file) {
  std::map<std::string, const pt::Json*> out;
  if (const pt::Json* probes = member_array(file, "probes"))
    for (const pt::Json& p : probes->array)
      if (p.type == pt::Json::Type::Object && !p.str("function").empty()) out[p.str("function")] = &p;
  return out;
}

std::string value_text(const pt::Json& v) {
  return v.type == pt::Json::Type::Number ? fmt("%.6g", v.number) : std::string("not a number");
}

// Whether `got` answers check `want` (the reference's) within its
// tolerance; otherwise *detail says where it first differs.
bool check_agrees(const pt::Json& want, const pt::Json* got, std::string* detail) {
  const std::string name = want.str("name");
  const pt::Json* wv = member_array(want, "values");
  const pt::Json* gv = got ? member_array(*got, "values") : nullptr;
  if (!wv) return true;  // nothing to compare
  if (!gv || gv->array.size() != wv->array.size()) {
    *detail = "check '" + name + "' gave " + (gv ? std::to_string(gv->array.size()) : std::string("no")) +
              " values, the reference " + std::to_string(wv->array.size());
    return false;
  }
  const double abs_tol = want.num("abs", 1e-5), rel_tol = want.num("rel", 1e-4);
  for (size_t i = 0; i < wv->array.size(); ++i) {
    const pt::Json &w = wv->array[i], &g = gv->array[i];
    const bool w_num = w.type == pt::Json::Type::Number, g_num = g.type == pt::Json::Type::Number;
    const bool ok = w_num && g_num ? std::fabs(g.number - w.number) <= abs_tol + rel_tol * std::fabs(w.number)
                                   : w_num == g_num;
    if (!ok) {
      *detail = "check '" + name + "', value " + std::to_string(i + 1) + " of " + std::to_string(wv->array.size()) +
                ": gave " + value_text(g) + ", the reference " + value_text(w);
      return false;
    }
  }
  return true;
}

}  // namespace

std::string reference_probes_path(const std::string& references_dir) {
  return (fs::path(references_dir) / "probes.json").string();
}

ProbeVerdicts compare_probes(const pt::Json& reference, const pt::Json& build, std::string* problem) {
  ProbeVerdicts out;
  if (problem) problem->clear();
  if (!member_array(build, "probes")) {
    if (problem) *problem = "no \"probes\" list";
    return out;
  }
  const auto got = by_function(build);
  for (const auto& [function, want] : by_function(reference)) {
    const auto g = got.find(function);
    if (g == got.end()) continue;  // not run: its part was not asked for
    ProbeVerdict v;
    v.function = function;
    v.part = int(want->num("part", 0));
    const std::string status = g->second->str("status");
    if (status != "ok") {
      v.agrees = false;
      // The status is the build's own text: only the grader's words go
      // into the report.
      v.detail = status.rfind("crashed", 0) == 0 ? "crashed while checked"
                 : status == "timed out"          ? "did not return within the checks' time"
                                                  : "did not finish its checks";
    } else if (const pt::Json* checks = member_array(*want, "checks")) {
      std::map<std::string, const pt::Json*> theirs;
      if (const pt::Json* c = member_array(*g->second, "checks"))
        for (const pt::Json& x : c->array) theirs[x.str("name")] = &x;
      for (const pt::Json& c : checks->array) {
        const auto t = theirs.find(c.str("name"));
        if (!check_agrees(c, t == theirs.end() ? nullptr : t->second, &v.detail)) {
          v.agrees = false;
          break;
        }
      }
    }
    out[function] = v;
  }
  return out;
}

bool run_probes(const RunSettings& s, int max_part, const std::string& dir, std::string* failure) {
  std::error_code ec;
  fs::remove_all(dir, ec);
  fs::create_directories(dir, ec);
  if (ec) {
    *failure = "cannot create " + dir + ": " + ec.message();
    return false;
  }
  const std::string abs_dir = fs::absolute(dir).string();
  const std::string binary = fs::absolute(s.pathtracer).string();
  const std::string part = std::to_string(std::clamp(max_part, 1, 9));
  Staging staging;
  const Account* account = s.sandbox.account();
  std::vector<std::string> argv;
  if (s.sandbox.on()) {
    std::string why;
    if (!staging.stage(s.sandbox, account, {binary}, &why)) {
      *failure = "grader error: " + why;
      return false;
    }
    argv = staging.command(
        {staging.input_path(binary), "--probe", staging.out_path() + "/probes.json", "--part", part});
  } else {
    argv = {binary, "--probe", abs_dir + "/probes.json", "--part", part};
  }
  Limits limits;
  limits.wall_seconds = 120 * s.timeout_scale;
  limits.cpu_seconds = limits.wall_seconds;
  limits.memory_bytes = s.memory_bytes;
  limits.file_bytes = kMaxProbeBytes;
  if (account) limits.run_uid = int(account->uid), limits.run_gid = int(account->gid);
  limits.clear_environment = s.sandbox.on();
  limits.no_network = s.sandbox.mode == SandboxMode::User;
  const ChildResult child = run_child(argv, s.sandbox.on() ? staging.workdir() : abs_dir, abs_dir + "/stdout.txt",
                                      abs_dir + "/stderr.txt", limits);
  if (account) kill_account_processes(*account);
  if (s.sandbox.on()) {
    std::vector<std::string> refused;
    if (directory_bytes(staging.workdir()) <= kMaxProbeBytes) staging.collect({"probes.json"}, abs_dir, kMaxProbeBytes, &refused);
  }
  if (!child.started || child.timed_out || child.signal != 0 || child.exit_code != 0) {
    *failure = describe(child, limits);
    return false;
  }
  const fs::file_status st = fs::symlink_status(abs_dir + "/probes.json", ec);
  if (!fs::is_regular_file(st)) {
    *failure = "wrote no function checks";
    return false;
  }
  return true;
}

ProbeVerdicts probe_verdicts_for_folder(const std::string& dir, const std::string& references_dir) {
  std::error_code ec;
  const std::string mine = dir + "/probes/probes.json", theirs = reference_probes_path(references_dir);
  if (!fs::is_regular_file(fs::symlink_status(mine, ec)) || !fs::is_regular_file(theirs, ec)) return {};
  if (fs::file_size(mine, ec) > kMaxProbeBytes) return {};
  try {
    return compare_probes(pt::read_json_file(theirs), pt::read_json_file(mine));
  } catch (const std::exception&) {
    return {};
  }
}

std::vector<std::string> probe_lines(const ProbeVerdicts& verdicts) {
  std::vector<std::string> lines;
  for (const auto& [function, v] : verdicts)
    if (!v.agrees) lines.push_back("Function check: " + function + " (part " + std::to_string(v.part) +
                                   ") answers differently from the reference's: " + v.detail);
  return lines;
}

}  // namespace grader
