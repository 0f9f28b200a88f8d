// The grader's image cases as the viewer's settings, so that the page can
// offer "use case settings" and tell when a render is one a case grades.
#pragma once
#include <string>
#include <vector>

#include "grader/src/case_list.h"
#include "grader/src/hints.h"
#include "viewer/file_access.h"
#include "pathtracer/options.h"

namespace pt::viewer {

// A grading case as the viewer's settings: its part and options on its
// scene (when the page may open it).
struct ViewerCase {
  grader::Case c;
  RenderOptions opts;
  bool available = false;  // its scene is in an allowed folder
};

// The image cases of grader/cases.txt under `source_dir` (none when it
// cannot be read).
std::vector<ViewerCase> load_cases(const std::string& source_dir, const FileAccess& files);

// The known bugs of grader/known_bugs.json under `source_dir`, for the
// difference overlay's likely causes: none when the file is missing, and
// a warning on stderr as well when it cannot be read.
grader::Catalogue load_catalogue(const std::string& source_dir);

// The case named `name`, or null.
const ViewerCase* find_case(const std::vector<ViewerCase>& cases, const std::string& name);

// What decides a render's image (not the threads, the seed or the BVH's
// build settings): a render compares with a case when these agree.
std::string image_key(RenderOptions o);

}  // namespace pt::viewer
