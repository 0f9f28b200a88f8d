// The parsed COLLADA document: the file read and checked to be COLLADA,
// every element with an id indexed, "#id" references followed, and the
// document-level choices (the up axis, the visual scene to load).
#pragma once
#include <string>
#include <string_view>
#include <unordered_map>

#include "common/mat4.h"
#include "common/collada/messages.h"

namespace pt::collada {

class Document {
 public:
  explicit Document(Messages& msg) : msg_(msg) {}
  Document(const Document&) = delete;
  Document& operator=(const Document&) = delete;

  // Reads and parses the file, requires a <COLLADA> root and indexes ids.
  void read(const std::string& path);

  const XMLElement* root() const { return doc_.RootElement(); }

  // The element with this id (the first one in document order), or null.
  const XMLElement* find(std::string_view id) const;

  // Follows the "#id" reference in attribute `attr` of `from`, which must
  // name an element with tag `tag`.
  const XMLElement* resolve(const XMLElement* from, const char* attr, const char* tag) const;

  // The transform from the file's axes to the world's Y-up axes, from
  // <asset><up_axis> (required).
  Mat4 up_axis_transform() const;

  // The <visual_scene> that <scene> names, else the first one.
  const XMLElement* visual_scene();

 private:
  void index_ids();

  Messages& msg_;
  tinyxml2::XMLDocument doc_;
  std::unordered_map<std::string_view, const XMLElement*> ids_;
};

// The first <extra><technique profile="CGL"> of `owner` that has content:
// where the course's extensions (spheres, materials, lights) live.
const XMLElement* cgl_technique(const XMLElement* owner);

}  // namespace pt::collada
