// Grading one case: render it with the binary under test, check the
// outputs, score the image (and rate image, and costs) against the
// reference, and turn that into points and a one-line verdict.
#pragma once
#include <string>
#include <vector>

#include "case_list.h"
#include "json.h"
#include "reference.h"
#include "run_case.h"

namespace grader {

// How a case ended. Failed: the submission is wrong. Error: the grader
// could not judge it (no reference for the case).
enum class Verdict { Passed, Failed, Error };
const char* verdict_name(Verdict v);

// Bounds of the cost checks, relative to the reference's recorded figures.
// From part 2 on every case checks them: a BVH that is correct but tests
// too much (for camera and bounce rays, or only for shadow rays) loses the
// case's points. The slack covers scenes where the reference needs almost
// no tests (shadow rays under an open sky).
struct CostBounds {
  double tests_factor = 8.0;     // tests per query <= 8x the reference's + slack, for each kind of query
  double tests_slack = 4.0;     // a leaf of 4 primitives where the reference enters none
  double shadow_factor = 1.5;    // shadow rays per closest-hit query <= 1.5x the reference's
  double min_speedup = 10.0;     // speedup: part 1 tests per ray / part 2's
};

struct CaseResult {
  Case c;
  Verdict verdict = Verdict::Error;
  double score = 0, max_score = 0;
  std::string message;       // one line: why it passed or failed
  std::string metric;        // the statistics, short
  double relmse = -1;        // -1: not scored
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
  std::string command;       // what was run
  std::string log;           // the candidate's output, sanitised excerpt
  std::string dir;           // where its files are (images for the HTML report)
};

// How a case's image is scored against its reference: by value when the
// reference is deterministic, else the z tests at the case's sample count.
ScoreOptions case_score_options(const Case& c, const Reference& ref);

// Writes candidate.png, reference.png and error.png into the case folder
// for the HTML report (when there is an image).
CaseResult grade_case(const RunSettings& run, const std::string& reference_root, const Case& c,
                      uint64_t seed, const std::string& case_dir, const CostBounds& bounds);

// Whether the case's render printed a TODO line that dooms it (a stub of
// its own part or an earlier one, see todo_dooms): "not implemented".
bool not_implemented(const CaseResult& r);

// Per-case results survive as JSON so that shards can be merged.
std::string case_result_json(const CaseResult& r);
bool case_result_from_json(const Json& j, CaseResult* r);

}  // namespace grader
