#include "common/todo.h"

#include <cstdio>
#include <filesystem>
#include <mutex>
#include <set>

// The repository's root, as the build knows it (CMake sets it); stub paths
// are printed relative to it.
#ifndef PT_SOURCE_DIR
#define PT_SOURCE_DIR ""
#endif

#include "common/path_recorder.h"

namespace pt {

namespace {

std::mutex& print_mutex() {
  static std::mutex mu;
  return mu;
}

// `file` from the repository's root: without the build's source folder; a
// relative name (a compiler given paths relative to a build folder inside
// the tree, as under ccache: "../../stages/...") without its leading "../";
// or (a tree built from elsewhere, or without the definition) from its last
// "stages/" folder on; otherwise as it is.
std::string from_root(const char* file) {
  const std::string path = std::filesystem::path(file).lexically_normal().string();
  const std::string root = PT_SOURCE_DIR;
  if (!root.empty() && path.size() > root.size() + 1 && path.compare(0, root.size(), root) == 0 &&
      path[root.size()] == '/')
    return path.substr(root.size() + 1);
  if (!path.empty() && path[0] != '/') {
    size_t from = 0;
    while (path.compare(from, 3, "../") == 0) from += 3;
    if (from < path.size()) return path.substr(from);
  }
  size_t at = path.rfind("stages/");
  while (at != std::string::npos) {
    if (at == 0 || path[at - 1] == '/') return path.substr(at);
    at = path.rfind("stages/", at - 1);
  }
  return path;
}

}  // namespace

// The linker's bounds of the section the PT_TODO lines fill (weak: a
// program without a stub has no such section).
extern "C" {
extern const TodoSite __start_pt_todo_sites[] __attribute__((weak));
extern const TodoSite __stop_pt_todo_sites[] __attribute__((weak));
}

std::vector<TodoSite> todo_sites() {
  std::vector<TodoSite> out;
  if (!__start_pt_todo_sites || !__stop_pt_todo_sites) return out;
  for (const TodoSite* s = __start_pt_todo_sites; s < __stop_pt_todo_sites; ++s)
    if (s->part >= 1 && s->name) out.push_back(*s);
  return out;
}

std::string todo_message(int part, const char* name, const char* file, const char* note) {
  std::string s = "Part " + std::to_string(part) + ": " + name + " (" + from_root(file) + ")";
  if (note && *note) s += std::string("; ") + note;
  return s;
}

bool todo_print(int part, const char* name, const char* file, const char* note) {
  const std::string line = "TODO: implement " + todo_message(part, name, file, note) + "\n";
  std::lock_guard<std::mutex> lock(print_mutex());
  std::fputs(line.c_str(), stderr);
  return true;
}

void todo_reached(int part, const char* name, const char* file, const char* note) {
  // The debugger reports every stub a replayed sample reaches, not only the
  // first one the process met.
  if (PathRecorder* rec = active_path_recorder()) rec->on_todo(todo_message(part, name, file, note).c_str());
}

void todo_once(const char* what) {
  if (PathRecorder* rec = active_path_recorder()) rec->on_todo(what);
  static std::set<std::string> seen;
  std::lock_guard<std::mutex> lock(print_mutex());
  if (seen.insert(what).second) std::fprintf(stderr, "TODO: implement %s\n", what);
}

}  // namespace pt
