// The function checks (pathtracer/probe.h) as the grader reads them: a
// build's answers compared with the reference build's, function by
// function. They never score anything; they order the hints (hints.h): a
// function that answers its checks differently from the reference's is
// named first, one that answers them alike last.
#pragma once
#include <map>
#include <string>
#include <vector>

#include "common/json.h"
#include "grader/src/run_case.h"

namespace grader {

struct ProbeVerdict {
  std::string function;
  int part = 0;
  bool agrees = true;
  // When it does not: the first difference, in a student's words ("check
  // 'refract: wi of 12 directions', value 4: gave 0.31, the reference
  // 0.5"; "crashed (Segmentation fault)").
  std::string detail;
};
using ProbeVerdicts = std::map<std::string, ProbeVerdict>;  // by function

// Where the reference build's answers are kept: <references>/probes.json.
std::string reference_probes_path(const std::string& references_dir);

// A build's answers (`pathtracer --probe`) against the reference's, for
// every function the reference answered. A function the build did not
// answer (left out, or its part not run) is not judged. Never throws: a
// malformed build file judges nothing ("" in *problem says why not).
ProbeVerdicts compare_probes(const pt::Json& reference, const pt::Json& build, std::string* problem = nullptr);

// Runs `pathtracer --probe` for parts 1 to `max_part` in the run's sandbox,
// into dir/probes.json. False, with *failure set, when it did not write it.
bool run_probes(const RunSettings& s, int max_part, const std::string& dir, std::string* failure);

// The build's answers in graded folder `dir` (dir/probes.json) against the
// references' in `references_dir`; empty when either is missing or
// unreadable.
ProbeVerdicts probe_verdicts_for_folder(const std::string& dir, const std::string& references_dir);

// The report's lines on the checks that disagree ("Function check: ...").
std::vector<std::string> probe_lines(const ProbeVerdicts& verdicts);

}  // namespace grader
