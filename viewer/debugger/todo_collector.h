// What the debugger's tools share: the TODO stubs a call of the build's
// code reached, collected while installed as the thread's path recorder.
#pragma once
#include <set>
#include <string>
#include <vector>

#include "common/path_recorder.h"

namespace pt::debug {

class TodoCollector final : public PathRecorder {
 public:
  void on_todo(const char* what) override {
    if (seen_.insert(what).second) todos.push_back(std::string("TODO: implement ") + what);
  }
  std::vector<std::string> todos;

 private:
  std::set<std::string> seen_;
};

}  // namespace pt::debug
