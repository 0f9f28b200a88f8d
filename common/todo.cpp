#include "todo.h"

#include <cstdio>
#include <mutex>
#include <set>
#include <string>

#include "path_recorder.h"

namespace pt {

void todo_once(const char* what) {
  // The debugger reports every stub it reaches, not only the first.
  if (PathRecorder* rec = active_path_recorder()) rec->on_todo(what);
  static std::mutex mu;
  static std::set<std::string> seen;
  std::lock_guard<std::mutex> lock(mu);
  if (seen.insert(what).second) std::fprintf(stderr, "TODO: implement %s\n", what);
}

}  // namespace pt
