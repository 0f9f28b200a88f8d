// `grader compare`: a render a student made by hand, next to the reference
// of the grading case it renders, with a difference image. For checking
// one's work between grading runs: the course's standard commands are the
// grading cases' commands (`--list` prints them).
#pragma once
#include <string>
#include <vector>

#include "grader/src/case_list.h"
#include "grader/src/hints.h"
#include "grader/src/rules.h"

namespace grader {

// Prints every case with the exact command that renders it (`pathtracer`
// is the binary to name, `scenes` the scenes folder, both as the user
// should type them).
void print_case_commands(const std::vector<Case>& cases, const std::string& pathtracer, const std::string& scenes);

// Compares FILES with the reference of `c`: one .png (an 8-bit comparison,
// no verdict), one .pfm (the grader's statistics with the reference's
// noise standing in for yours, and a verdict) or several .pfm renders of
// the case at different seeds (judged with their own noise, as `grader
// run` judges a build: the verdict the grader would give the image).
// Writes OUT/compare_<case>.png (render | reference | difference) and
// OUT/compare_<case>.html, and prints a summary. A .pfm that differs also
// gets the likely causes from `catalogue`'s known bugs on this case
// (hints.h: the lines `grader run` prints; none when the catalogue is
// empty). Returns the exit status: 0 matches (or a PNG compared), 1
// differs. Throws std::runtime_error naming the file for bad input
// (unreadable, wrong size, no reference).
int compare_render(const Case& c, const std::string& references, const std::vector<std::string>& files,
                   const std::string& out_dir, const Rules& rules, const Catalogue& catalogue,
                   const CaseGroups& groups);

}  // namespace grader
