// Helpers shared by the tests: temporary folders, running the pathtracer
// executable, reading PNGs back, and locating the course's scene files.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace pt::test {

// Path of a course scene file in ../shared/cs184-scenes. When that folder is
// absent the calling test is skipped: the process exits with code 77, which
// ctest reports as "Skipped" (each test case runs in its own process).
std::string course_scene(const std::string& name);

// A tiny valid scene (Y up): one triangle of the default material, wound
// clockwise as seen from the camera on +Z so that its recomputed normal
// (reversed, as for every lone polygon) faces the camera; no lights.
extern const char* const kTinyTriangleScene;

// Path of one of the project's own scene files (scenes/NAME).
std::string project_scene(const std::string& name);

// A fresh temporary folder, removed with everything in it on destruction.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::string& path() const { return path_; }
  std::string file(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

void write_text(const std::string& path, const std::string& text);

// PT_TEST_TIMEOUT_SCALE from the environment (README, "Tests"): a number > 0
// such as 2 or 2.5, 1 when unset, by which a test multiplies every timeout it
// gives a program it runs (as ctest multiplies the tests' own TIMEOUT).
// Throws std::runtime_error naming the variable when it is not such a number.
double timeout_scale();
bool file_exists(const std::string& path);
std::vector<std::string> list_dir(const std::string& dir);

struct RunResult {
  int exit_code = -1;
  std::string out;  // standard output
  std::string err;  // standard error
};

// Runs the built pathtracer executable with `args` (no shell involved).
RunResult run_pathtracer(const std::vector<std::string>& args, const std::string& cwd = "");

struct Png {
  unsigned width = 0, height = 0;
  std::vector<unsigned char> rgb;  // top row first, 3 bytes per pixel
};
// Decodes a PNG; returns false when the file is missing or not a PNG.
bool read_png(const std::string& path, Png* png);

}  // namespace pt::test
