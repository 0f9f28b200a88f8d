// Grading one case: render it with the binary under test, check the
// outputs, run the checks that apply (checks.h) against the reference, and
// turn them into points and a one-line verdict.
#pragma once
#include <string>
#include <vector>

#include "grader/src/case_list.h"
#include "grader/src/case_result.h"
#include "grader/src/checks.h"
#include "grader/src/reference.h"
#include "grader/src/rules.h"
#include "grader/src/run_case.h"

namespace grader {

// How a case's image is scored against its reference: by value when the
// reference is deterministic, else the z tests at the case's sample count,
// at the image's share of the run's false-failure budget.
ScoreOptions case_score_options(const Case& c, const Reference& ref, const Rules& rules);
// For one image judged on its own (the viewer's difference overlay): the
// whole budget of a default Rules goes to it.
ScoreOptions case_score_options(const Case& c, const Reference& ref);

// Renders the case (a Monte Carlo case several times, rules.renders) with
// the binary under test, checks every output and grades it. Writes
// candidate.png (the renders' mean), reference.png and error.png into the
// case folder for the HTML report (when there is an image).
CaseResult grade_case(const RunSettings& run, const std::string& reference_root, const Case& c,
                      uint64_t seed, const std::string& case_dir, const Rules& rules);

// "Part 3 not implemented (TODO: estimate_direct_lighting_importance)" from
// the TODO lines that doom a case of part `part` (todo_dooms), or "".
std::string not_implemented_message(const std::vector<std::string>& todo, int part);

// Whether the case's render printed a TODO line that dooms it (a stub of
// its own part or an earlier one, see todo_dooms).
bool doomed_by_todo(const CaseResult& r);

}  // namespace grader
