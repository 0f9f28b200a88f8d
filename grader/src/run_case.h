// One render of one case by one pathtracer binary, in its own folder, with
// every output checked: the step shared by grading, making references and
// calibrating.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "grader/src/case_list.h"
#include "grader/src/child_process.h"
#include "common/json.h"
#include "grader/src/sandbox.h"
#include "grader/src/scoring.h"

namespace grader {

using pt::Json;

struct RunSettings {
  std::string pathtracer;      // the binary under test
  std::string scenes_dir;      // where case scenes are found
  int threads = 1;             // -t for each render
  double timeout_scale = 1.0;  // multiplies each case's timeout
  uint64_t memory_bytes = 4ull << 30;
  uint64_t output_bytes = 256ull << 20;  // per file and for the folder
  Sandbox sandbox;             // where each render runs (sandbox.h)
};

struct RenderOutput {
  bool ok = false;          // ran, exited 0 and wrote valid images of the right size
  std::string failure;      // one line: why not
  ChildResult child;
  double seconds = 0;       // wall-clock, whole process
  ImageBuffer radiance;     // from the PFM
  ImageBuffer rate;         // the rate in every channel, when `want_rate`
  bool has_stats = false;
  Json stats;               // --stats-json
  std::string log;          // stdout + stderr excerpt, sanitised
  // The render's "TODO: implement Part N: ..." lines (a starter-kit stub
  // prints one the first time it is reached), in the order printed.
  std::vector<std::string> todo;
  bool stopped_at_todo = false;  // stopped as soon as it printed a TODO line that dooms the case (todo_dooms)
};

// The part number of a "TODO: implement Part N: ..." line, or 0.
int todo_part(const std::string& line);

// Whether a stub of part `todo` printing its TODO line means that a case of
// part `case_part` cannot pass: any part up to the case's, except Part 2
// for later parts (the stub BVH tests every primitive: slow, but correct).
bool todo_dooms(int todo, int case_part);

// The size `-r W H` in a case's options (the course's default 800 x 600).
void case_resolution(const Case& c, int* width, int* height);

// The integer after `flag` in a case's options, or `fallback`.
int case_int_option(const Case& c, const std::string& flag, int fallback);

// stats[num] / stats[den] of a --stats-json object; 0 when den is 0 or
// missing (tests per ray: "primitive_tests" / "rays").
double stat_ratio(const Json& stats, const char* num, const char* den);

// The files a render of `c` reads: the scene, then each file its options
// name (-c camera settings, -e environment map), as paths the grader can
// open. Relative option files are looked up beside the case list
// (c.files_dir) first, then beside the scenes.
std::vector<std::string> case_input_files(const RunSettings& s, const Case& c);

// Renders `c` with --part `part` and seed `seed` into `dir` (created,
// emptied first). With a sandbox (s.sandbox), the render runs in it and only
// its image files and statistics come back into `dir`. A render that prints a TODO line that dooms a case of
// part `part` is stopped there (its failure says so). Never throws: every problem becomes
// `failure`.
RenderOutput render_case(const RunSettings& s, const Case& c, int part, uint64_t seed, const std::string& dir,
                         bool want_rate);

}  // namespace grader
