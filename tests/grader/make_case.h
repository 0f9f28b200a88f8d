// A grading case made in a test, without a case list.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "grader/src/case_list.h"

namespace grader::test {

inline Case make_case(const std::string& name, int part, const std::string& scene,
                      std::vector<std::string> options = {}) {
  Case c;
  c.name = name;
  c.part = part;
  c.scene = scene;
  c.options = std::move(options);
  return c;
}

}  // namespace grader::test
