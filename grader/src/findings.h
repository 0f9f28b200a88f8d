// What a grading run noticed across its cases, beyond each case's own
// verdict: conventions of the kit that bite course-style code, said where
// they first show. One line each, in the student's words, with the README
// section to read; the reports print them above the table.
#pragma once
#include <string>
#include <vector>

#include "grader/src/case_result.h"

namespace grader {

// - NaN pixels: the first part and case where they appear, and how many
//   cases have them (a NaN fails a case outright, so later parts' cases
//   that inherit it say nothing new);
// - self-shadowing: part 3's light-sampling images uniformly about half as
//   bright (0.3 to 0.7 of the reference in its lit and its brightest
//   regions alike) in two or more cases: shadow rays that start on their
//   own surface.
std::vector<std::string> run_findings(const std::vector<CaseResult>& results);

}  // namespace grader
