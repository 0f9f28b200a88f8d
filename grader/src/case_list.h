// The grading cases, read from a data file (grader/cases.txt).
#pragma once
#include <string>
#include <vector>

namespace grader {

// What a case checks besides the image and, from part 2 on, the costs
// (intersection tests per query, shadow rays per query) that every case
// checks against the reference's.
enum class CaseKind {
  Image,        // the image against the reference
  Rate,         // image and sample-rate image (adaptive sampling)
  Speedup,      // render with --part 1 and --part 2: the BVH's speed-up
  Probability,  // image, and the -e map's probability image (--env-probability)
};

struct Case {
  std::string name;
  int part = 1;
  CaseKind kind = CaseKind::Image;
  double points = 1.0;
  double timeout_seconds = 60.0;
  std::string scene;                // relative to the scenes folder
  std::vector<std::string> options; // pathtracer options (no output flags)
  int line = 0;                     // in the case file, for messages
  // The case list's folder: files that options name (-c, -e) are looked up
  // here first, then beside the scenes.
  std::string files_dir;
  // A hidden case (grader run --hidden-cases): graded like the others, but
  // students see only its part's total and its verdict, never its name or
  // settings; its reference lies apart (--hidden-references).
  bool hidden = false;
};

const char* kind_name(CaseKind kind);
// The kind named `s` ("image", "rate", ...); false when there is none.
bool parse_kind(const std::string& s, CaseKind* kind);

// Reads the case file. Throws std::runtime_error("<path>:<line>: <what>")
// on any malformed line, unknown kind or duplicate name.
std::vector<Case> read_cases(const std::string& path);

// A stable digest of what a case renders (scene, part, options): a reference
// made for one definition is never used for another.
std::string case_digest(const Case& c);

// "--part 3 -s 8 -l 4 CBbunny.dae": the case's command, without binary or
// output flags, for reports.
std::string case_command(const Case& c);

}  // namespace grader
