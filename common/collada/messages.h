// The loader's errors and warnings: one line each, naming the file, the
// element (tag, id and line) and what is wrong, plus the small formatting
// helpers their texts use.
#pragma once
#include <initializer_list>
#include <string>
#include <string_view>
#include <unordered_set>
#include <vector>

#include <tinyxml2.h>

#include "common/vec3.h"

namespace pt::collada {

using tinyxml2::XMLElement;

// Control characters become spaces, so that a message stays one line.
std::string one_line(std::string s);

// A piece of the input in quotes for a message, shortened when long.
std::string quote(std::string_view s);

// Numbers as messages print them (six significant digits).
std::string fmt(double v);
std::string fmt(const Vec3d& v);

// Reports the problems of one scene file.
class Messages {
 public:
  Messages(const std::string& path, std::vector<std::string>* warnings) : path_(path), warnings_(warnings) {}

  // "<tag id="..."> (line N)", naming an element for a message.
  std::string describe(const XMLElement* e) const;

  // Throws SceneError "<file>: <element>: <what>".
  [[noreturn]] void fail(const XMLElement* e, const std::string& what) const;
  // Throws SceneError "<file>: <what>", for the file as a whole.
  [[noreturn]] void fail_file(const std::string& what) const;

  void warn(const XMLElement* e, const std::string& what);
  // A warning about an element itself, given once however often the
  // element is visited (library nodes are visited once per instance).
  void warn_once(const XMLElement* e, const std::string& what);

  // Warns about every child of `parent` whose name is not in `known`: an
  // element the loader does not read where it would read its content (a
  // misspelt <instance_geometry>) would otherwise silently vanish.
  void check_children(const XMLElement* parent, std::initializer_list<std::string_view> known);

 private:
  const std::string path_;
  std::vector<std::string>* warnings_;
  std::unordered_set<const XMLElement*> warned_;
};

}  // namespace pt::collada
