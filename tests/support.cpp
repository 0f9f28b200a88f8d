#include "tests/support.h"

#include <fcntl.h>
#include <lodepng.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>

extern char** environ;

namespace pt::test {

namespace fs = std::filesystem;

const char* const kTinyTriangleScene = R"(<?xml version="1.0"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><up_axis>Y_UP</up_axis></asset>
  <library_cameras><camera id="cam"><optics><technique_common><perspective>
    <xfov>50</xfov><aspect_ratio>1.333333</aspect_ratio><znear>0.1</znear><zfar>100</zfar>
  </perspective></technique_common></optics></camera></library_cameras>
  <library_geometries><geometry id="tri"><mesh>
    <source id="tri-pos"><float_array id="tri-pos-array" count="9">-1 -1 0 0 1 0 1 -1 0</float_array>
      <technique_common><accessor source="#tri-pos-array" count="3" stride="3"/></technique_common></source>
    <vertices id="tri-v"><input semantic="POSITION" source="#tri-pos"/></vertices>
    <triangles count="1"><input semantic="VERTEX" source="#tri-v" offset="0"/><p>0 1 2</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="Scene">
    <node id="Camera"><matrix>1 0 0 0 0 1 0 0 0 0 1 5 0 0 0 1</matrix><instance_camera url="#cam"/></node>
    <node id="Tri"><instance_geometry url="#tri"/></node>
  </visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#Scene"/></scene>
</COLLADA>
)";

std::string course_scene(const std::string& name) {
  const fs::path dir = PT_COURSE_SCENES;
  if (!fs::is_directory(dir)) {
    std::cout << "SKIPPED: course scenes not found at " << dir << "\n";
    std::exit(77);
  }
  return (dir / name).string();
}

std::string project_scene(const std::string& name) { return std::string(PT_PROJECT_SCENES) + "/" + name; }

TempDir::TempDir() {
  std::string tmpl = (fs::temp_directory_path() / "pt-test-XXXXXX").string();
  if (!mkdtemp(tmpl.data())) throw std::runtime_error("mkdtemp failed");
  path_ = tmpl;
}

TempDir::~TempDir() {
  std::error_code ec;
  fs::remove_all(path_, ec);
}

void write_text(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary);
  f << text;
  if (!f) throw std::runtime_error("cannot write " + path);
}

double timeout_scale() {
  const char* v = std::getenv("PT_TEST_TIMEOUT_SCALE");
  if (!v || !*v) return 1.0;
  // The grammar of tests/timeout_scale/: digits, then a point and digits.
  const std::string s = v;
  const size_t digits = s.find_first_not_of("0123456789");
  const bool well_formed =
      digits != 0 && (digits == std::string::npos ||
                      (s[digits] == '.' && s.find_first_not_of("0123456789", digits + 1) == std::string::npos));
  const double scale = well_formed ? std::strtod(v, nullptr) : 0.0;
  if (!(scale > 0)) throw std::runtime_error("PT_TEST_TIMEOUT_SCALE=" + s + ": not a number > 0 such as 2 or 2.5");
  return scale;
}

bool file_exists(const std::string& path) { return fs::exists(path); }

std::vector<std::string> list_dir(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  return names;
}

static std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

RunResult run_pathtracer(const std::vector<std::string>& args, const std::string& cwd) {
  TempDir io;
  const std::string out_path = io.file("stdout"), err_path = io.file("stderr");
  std::vector<std::string> argv_s = {PT_PATHTRACER_EXE};
  argv_s.insert(argv_s.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& s : argv_s) argv.push_back(s.data());
  argv.push_back(nullptr);

  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&fa, 1, out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&fa, 2, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (!cwd.empty()) posix_spawn_file_actions_addchdir_np(&fa, cwd.c_str());
  pid_t pid = 0;
  RunResult r;
  if (posix_spawn(&pid, argv[0], &fa, nullptr, argv.data(), environ) != 0) {
    posix_spawn_file_actions_destroy(&fa);
    r.err = "posix_spawn failed";
    return r;
  }
  posix_spawn_file_actions_destroy(&fa);
  int status = 0;
  waitpid(pid, &status, 0);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  r.out = slurp(out_path);
  r.err = slurp(err_path);
  return r;
}

bool read_png(const std::string& path, Png* png) {
  if (!fs::exists(path)) return false;
  return lodepng::decode(png->rgb, png->width, png->height, path, LCT_RGB, 8) == 0;
}

}  // namespace pt::test
