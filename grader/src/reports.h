// What a grading run leaves behind, for people and for Gradescope. Every
// file is written to a temporary name and renamed into place.
//   report.txt     the terminal table
//   timing.md      the write-up-style timing tables
//   results.json   Gradescope's format
//   report.html    one self-contained page: candidate, reference and
//                  error map side by side for every case
#pragma once
#include <string>
#include <vector>

#include "grader/src/grade.h"

namespace grader {

struct RunInfo {
  std::string pathtracer;   // the binary graded
  std::string started;      // UTC
  double wall_seconds = 0;
  int jobs = 1, threads = 1;
  unsigned long long seed = 1;
  // "Likely cause ..." lines from the known bugs' signatures (hints.h).
  std::vector<std::string> hints;
};

// The table, the points per part, what the run noticed and the hints.
std::string terminal_table(const std::vector<CaseResult>& results, const std::vector<std::string>& hints = {});
std::string timing_tables(const std::vector<CaseResult>& results);
std::string gradescope_json(const std::vector<CaseResult>& results, const RunInfo& info);
std::string html_report(const std::vector<CaseResult>& results, const RunInfo& info);

// Writes all four into `dir`. Throws std::runtime_error naming the file on
// failure.
void write_reports(const std::string& dir, const std::vector<CaseResult>& results, const RunInfo& info);

}  // namespace grader
