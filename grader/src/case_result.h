// What grading one case found, and its JSON form (cases/<name>/result.json,
// what `grader merge` reads back): one table of fields drives both the
// writer and the reader.
#pragma once
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "grader/src/case_list.h"
#include "common/json.h"

namespace grader {

using pt::Json;

// How a case ended. Failed: the submission is wrong. Error: the grader
// could not judge it (no reference for the case).
enum class Verdict { Passed, Failed, Error };
const char* verdict_name(Verdict v);

struct CaseResult {
  Case c;
  Verdict verdict = Verdict::Error;
  double score = 0, max_score = 0;
  std::string message;       // one line: why it passed or failed
  std::string metric;        // the statistics, short
  double relmse = -1;        // -1: not scored
  double noise_ratio = -1;   // the candidate's variance over the reference's (-1: not measured)
  double tail_ratio = -1;    // the same, no pixel's share capped (fireflies counted in full)
  double relmse_noise = -1;  // the relMSE the renders' own noise gives (-1: not measured)
  double seconds = 0;        // wall-clock of the candidate's render(s)
  double render_seconds = -1;   // the renderer's own figure, when reported
  double reference_seconds = -1;
  double speed_ratio = -1;   // candidate render time / reference's (>1 = slower)
  double tests_per_ray = -1, reference_tests_per_ray = -1;
  // Per kind of query: primitive tests per closest-hit query and per shadow
  // query, and shadow queries per closest-hit query (-1: not measured).
  double closest_tests = -1, reference_closest_tests = -1;
  double shadow_tests = -1, reference_shadow_tests = -1;
  double shadow_per_query = -1, reference_shadow_per_query = -1;
  std::vector<std::string> todo;  // the render's "TODO: implement Part N: ..." lines
  double mrays_per_second = -1;
  double triangles = -1;
  double part1_seconds = -1, speedup = -1;  // speedup cases
  // How the result differs from the reference, in noise-free figures
  // (signature.h; cost ratios and what went wrong added by grade_case).
  std::map<std::string, double> signature;
  std::string command;       // what was run
  std::string log;           // the candidate's output, sanitised excerpt
  std::string dir;           // where its files are (images for the HTML report)
};

// One member of result.json: its name, how it is written from a result and
// how it is read back into one (a missing or mistyped member leaves the
// field at the reader's fallback, as a result of an older grader may lack it).
struct CaseResultField {
  std::string name;
  std::function<Json(const CaseResult& r)> write;
  std::function<void(const Json& member, CaseResult* r)> read;  // member: Null when absent
};

// The fields of result.json, in the order they are written.
const std::vector<CaseResultField>& case_result_fields();

// Per-case results survive as JSON so that shards can be merged.
std::string case_result_json(const CaseResult& r);
// False when `j` is not an object with a case name.
bool case_result_from_json(const Json& j, CaseResult* r);

}  // namespace grader
