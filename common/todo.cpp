#include "todo.h"

#include <cstdio>
#include <mutex>
#include <set>
#include <string>

namespace pt {

void todo_once(const char* what) {
  static std::mutex mu;
  static std::set<std::string> seen;
  std::lock_guard<std::mutex> lock(mu);
  if (seen.insert(what).second) std::fprintf(stderr, "TODO: implement %s\n", what);
}

}  // namespace pt
