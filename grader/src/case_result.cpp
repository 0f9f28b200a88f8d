#include "grader/src/case_result.h"

#include <filesystem>

namespace grader {

namespace fs = std::filesystem;

const char* verdict_name(Verdict v) {
  switch (v) {
    case Verdict::Passed: return "passed";
    case Verdict::Failed: return "failed";
    case Verdict::Error: return "error";
  }
  return "?";
}

namespace {

// A double member; `fallback` when absent or not a number (null stands
// for a figure that was not finite).
CaseResultField number(const char* name, double CaseResult::*field, double fallback) {
  return {name, [field](const CaseResult& r) { return pt::json_real(r.*field); },
          [field, fallback](const Json& m, CaseResult* r) {
            r->*field = m.type == Json::Type::Number ? m.number : fallback;
          }};
}

CaseResultField text(const char* name, std::string CaseResult::*field) {
  return {name, [field](const CaseResult& r) { return pt::json_text(r.*field); },
          [field](const Json& m, CaseResult* r) { r->*field = m.type == Json::Type::String ? m.string : ""; }};
}

std::string string_of(const Json& m) { return m.type == Json::Type::String ? m.string : ""; }

std::vector<CaseResultField> make_fields() {
  std::vector<CaseResultField> f;
  f.push_back({"name", [](const CaseResult& r) { return pt::json_text(r.c.name); },
               [](const Json& m, CaseResult* r) { r->c.name = string_of(m); }});
  f.push_back({"part", [](const CaseResult& r) { return pt::json_int(r.c.part); },
               [](const Json& m, CaseResult* r) { r->c.part = m.type == Json::Type::Number ? int(m.number) : 0; }});
  f.push_back({"kind", [](const CaseResult& r) { return pt::json_text(kind_name(r.c.kind)); },
               [](const Json& m, CaseResult* r) { parse_kind(string_of(m), &r->c.kind); }});
  f.push_back({"verdict", [](const CaseResult& r) { return pt::json_text(verdict_name(r.verdict)); },
               [](const Json& m, CaseResult* r) {
                 const std::string v = string_of(m);
                 r->verdict = v == "passed" ? Verdict::Passed : v == "failed" ? Verdict::Failed : Verdict::Error;
               }});
  f.push_back(number("score", &CaseResult::score, 0));
  // The case's points are what it could score.
  f.push_back({"max_score", [](const CaseResult& r) { return pt::json_real(r.max_score); },
               [](const Json& m, CaseResult* r) {
                 r->max_score = m.type == Json::Type::Number ? m.number : 0;
                 r->c.points = r->max_score;
               }});
  f.push_back(text("message", &CaseResult::message));
  f.push_back(text("metric", &CaseResult::metric));
  f.push_back(number("relmse", &CaseResult::relmse, -1));
  f.push_back(number("noise_ratio", &CaseResult::noise_ratio, -1));
  f.push_back(number("tail_ratio", &CaseResult::tail_ratio, -1));
  f.push_back(number("relmse_noise", &CaseResult::relmse_noise, -1));
  f.push_back(number("seconds", &CaseResult::seconds, 0));
  f.push_back(number("render_seconds", &CaseResult::render_seconds, -1));
  f.push_back(number("reference_seconds", &CaseResult::reference_seconds, -1));
  f.push_back(number("speed_ratio", &CaseResult::speed_ratio, -1));
  f.push_back(number("tests_per_ray", &CaseResult::tests_per_ray, -1));
  f.push_back(number("reference_tests_per_ray", &CaseResult::reference_tests_per_ray, -1));
  f.push_back(number("closest_tests", &CaseResult::closest_tests, -1));
  f.push_back(number("reference_closest_tests", &CaseResult::reference_closest_tests, -1));
  f.push_back(number("shadow_tests", &CaseResult::shadow_tests, -1));
  f.push_back(number("reference_shadow_tests", &CaseResult::reference_shadow_tests, -1));
  f.push_back(number("shadow_per_query", &CaseResult::shadow_per_query, -1));
  f.push_back(number("reference_shadow_per_query", &CaseResult::reference_shadow_per_query, -1));
  f.push_back({"todo",
               [](const CaseResult& r) {
                 std::vector<Json> lines;
                 for (const std::string& t : r.todo) lines.push_back(pt::json_text(t));
                 return pt::json_array(lines, true);
               },
               [](const Json& m, CaseResult* r) {
                 r->todo.clear();
                 for (const Json& e : m.array) r->todo.push_back(e.string);
               }});
  f.push_back(number("mrays_per_second", &CaseResult::mrays_per_second, -1));
  f.push_back(number("triangles", &CaseResult::triangles, -1));
  f.push_back(number("part1_seconds", &CaseResult::part1_seconds, -1));
  f.push_back(number("speedup", &CaseResult::speedup, -1));
  f.push_back({"signature",
               [](const CaseResult& r) {
                 Json o = pt::json_object();
                 for (const auto& [key, value] : r.signature) o.set(key, pt::json_real(value));
                 return o;
               },
               [](const Json& m, CaseResult* r) {
                 r->signature.clear();
                 for (const auto& [key, value] : m.members)
                   if (value.type == Json::Type::Number) r->signature[key] = value.number;
               }});
  f.push_back(text("command", &CaseResult::command));
  f.push_back({"scene", [](const CaseResult& r) { return pt::json_text(r.c.scene); },
               [](const Json& m, CaseResult* r) { r->c.scene = string_of(m); }});
  // Absolute, so that a merge run from another folder finds the images.
  f.push_back({"dir", [](const CaseResult& r) { return pt::json_text(fs::absolute(r.dir).string()); },
               [](const Json& m, CaseResult* r) { r->dir = string_of(m); }});
  f.push_back(text("log", &CaseResult::log));
  return f;
}

}  // namespace

const std::vector<CaseResultField>& case_result_fields() {
  static const std::vector<CaseResultField> fields = make_fields();
  return fields;
}

std::string case_result_json(const CaseResult& r) {
  Json j = pt::json_object();
  for (const CaseResultField& f : case_result_fields()) j.set(f.name, f.write(r));
  return pt::write_json(j);
}

bool case_result_from_json(const Json& j, CaseResult* r) {
  if (j.type != Json::Type::Object || j.str("name").empty()) return false;
  static const Json absent;
  for (const CaseResultField& f : case_result_fields()) {
    const Json* m = j.get(f.name);
    f.read(m ? *m : absent, r);
  }
  return true;
}

}  // namespace grader
