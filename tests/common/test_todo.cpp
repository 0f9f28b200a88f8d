// The starter kit's TODO lines (common/todo.h): the grader reads them, so
// their text is fixed: "TODO: implement Part N: <function> (<file>)".
#include <catch2/catch.hpp>

#include <algorithm>
#include <vector>
#include <cstdio>
#include <string>
#include <unistd.h>

#include "common/todo.h"

using namespace pt;

namespace {

// This file's folder, the repository's root, as the compiler names it.
std::string repository_root() {
  const std::string self = __FILE__;
  const std::string tail = "/tests/common/test_todo.cpp";
  REQUIRE(self.size() > tail.size());
  REQUIRE(self.compare(self.size() - tail.size(), tail.size(), tail) == 0);
  return self.substr(0, self.size() - tail.size());
}

// What `f` writes on stderr (file descriptor 2).
template <class F>
std::string stderr_of(F f) {
  std::fflush(stderr);
  std::FILE* tmp = std::tmpfile();
  REQUIRE(tmp != nullptr);
  const int saved = dup(2);
  REQUIRE(saved >= 0);
  REQUIRE(dup2(fileno(tmp), 2) >= 0);
  f();
  std::fflush(stderr);
  dup2(saved, 2);
  close(saved);
  std::string text;
  std::rewind(tmp);
  for (int c; (c = std::fgetc(tmp)) != EOF;) text += char(c);
  std::fclose(tmp);
  return text;
}

void stub_of_part_three() { PT_TODO(3); }

void stub_with_a_note() { PT_TODO_AS(2, "BVH::intersect", "testing every primitive"); }

void stub_with_its_own_note() { PT_TODO(4, "direct light only"); }

}  // namespace

TEST_CASE("a TODO message names the part, the function and the file from the repository's root", "[todo]") {
  const std::string root = repository_root();
  CHECK(todo_message(1, "generate_ray", (root + "/stages/part1_raytracing/camera_rays.cpp").c_str()) ==
        "Part 1: generate_ray (stages/part1_raytracing/camera_rays.cpp)");
  CHECK(todo_message(2, "BVH construction", (root + "/stages/part2_bvh/bvh_build.cpp").c_str(), "using one leaf") ==
        "Part 2: BVH construction (stages/part2_bvh/bvh_build.cpp); using one leaf");
  // A tree built from another folder (a student's kit): from its stages/ on.
  CHECK(todo_message(4, "at_least_one_bounce_radiance",
                     "/home/a/stages/kit/stages/part4_global_illumination/global_illumination.cpp") ==
        "Part 4: at_least_one_bounce_radiance (stages/part4_global_illumination/global_illumination.cpp)");
  // A compiler given paths relative to the build folder (ccache's base_dir
  // does that): from the root, whatever the folder's depth.
  CHECK(todo_message(3, "f", "../../tests/common/test_todo.cpp") == "Part 3: f (tests/common/test_todo.cpp)");
  CHECK(todo_message(3, "f", "../../../viewer/../stages/part3_direct_lighting/a.cpp") ==
        "Part 3: f (stages/part3_direct_lighting/a.cpp)");
  // "mystages/" is not a stages/ folder; a path with none is kept whole.
  CHECK(todo_message(5, "f", "/x/mystages/part5/a.cpp") == "Part 5: f (/x/mystages/part5/a.cpp)");
}

TEST_CASE("PT_TODO prints its line once, naming the enclosing function and this file", "[todo]") {
  const std::string printed = stderr_of([] {
    for (int i = 0; i < 3; ++i) stub_of_part_three();
  });
  CHECK(printed == "TODO: implement Part 3: stub_of_part_three (tests/common/test_todo.cpp)\n");
  // Reached again later: nothing more.
  CHECK(stderr_of([] { stub_of_part_three(); }).empty());
  CHECK(stderr_of([] { stub_with_a_note(); }) ==
        "TODO: implement Part 2: BVH::intersect (tests/common/test_todo.cpp); testing every primitive\n");
}

// Never called: a function of the program all the same, as a stub of the
// kit is (outside an unnamed namespace, so that it is compiled).
void never_called_stub_of_part_five();
void never_called_stub_of_part_five() { PT_TODO(5, "no pixel ever converges"); }

TEST_CASE("PT_TODO(part, note) says what the stub does meanwhile", "[todo]") {
  CHECK(stderr_of([] { stub_with_its_own_note(); }) ==
        "TODO: implement Part 4: stub_with_its_own_note (tests/common/test_todo.cpp); direct light only\n");
}

TEST_CASE("every PT_TODO line of the program is listed, whether it ran or not", "[todo]") {
  const std::vector<TodoSite> sites = todo_sites();
  const auto has = [&](int part, const std::string& name, const std::string& note) {
    return std::any_of(sites.begin(), sites.end(), [&](const TodoSite& s) {
      return s.part == part && name == s.name && note == s.note && std::string(s.file).find("test_todo.cpp") != std::string::npos;
    });
  };
  CHECK(has(3, "stub_of_part_three", ""));
  CHECK(has(2, "BVH::intersect", "testing every primitive"));
  CHECK(has(5, "never_called_stub_of_part_five", "no pixel ever converges"));  // never reached
  CHECK(has(4, "stub_with_its_own_note", "direct light only"));
}
