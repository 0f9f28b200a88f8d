// The parsed COLLADA document (see document.h).
#include "common/collada/document.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>
#include <vector>

#include "common/collada/xml_values.h"

namespace pt::collada {

namespace {

// A readable account of a tinyxml2 parse error: what kind, plus the
// parser's detail (e.g. the element's name) when it gives one.
std::string xml_error_text(const tinyxml2::XMLDocument& doc) {
  std::string kind;
  switch (doc.ErrorID()) {
    case tinyxml2::XML_ERROR_MISMATCHED_ELEMENT: kind = "an end tag does not match its start tag"; break;
    case tinyxml2::XML_ERROR_PARSING_ELEMENT: kind = "malformed or unclosed element"; break;
    case tinyxml2::XML_ERROR_PARSING_ATTRIBUTE: kind = "malformed attribute"; break;
    case tinyxml2::XML_ERROR_PARSING_TEXT: kind = "malformed text"; break;
    case tinyxml2::XML_ERROR_PARSING_CDATA: kind = "malformed CDATA section"; break;
    case tinyxml2::XML_ERROR_PARSING_COMMENT: kind = "malformed comment"; break;
    case tinyxml2::XML_ERROR_PARSING_DECLARATION: kind = "malformed declaration"; break;
    case tinyxml2::XML_ERROR_PARSING_UNKNOWN: kind = "malformed markup"; break;
    case tinyxml2::XML_ELEMENT_DEPTH_EXCEEDED: kind = "elements nested too deeply"; break;
    default: kind = "syntax error"; break;
  }
  // ErrorStr() reads "Error=NAME ErrorID=N (0xN) Line number=L[: detail]".
  const std::string full = doc.ErrorStr() ? doc.ErrorStr() : "";
  const size_t ln = full.find("Line number=");
  const size_t colon = ln == std::string::npos ? ln : full.find(": ", ln);
  if (colon != std::string::npos) kind += " (" + std::string(trim(std::string_view(full).substr(colon + 2))) + ")";
  return kind;
}

}  // namespace

void Document::read(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) msg_.fail_file("is a folder, not a scene file");
  std::ifstream in(path, std::ios::binary);
  if (!in) msg_.fail_file(std::string("cannot open file (") + std::strerror(errno) + ")");
  std::ostringstream content;
  content << in.rdbuf();
  if (in.bad()) msg_.fail_file("cannot read file");
  const std::string data = content.str();
  if (doc_.Parse(data.data(), data.size()) != tinyxml2::XML_SUCCESS) {
    if (doc_.ErrorID() == tinyxml2::XML_ERROR_EMPTY_DOCUMENT)
      msg_.fail_file("the file is empty or holds no XML element");
    msg_.fail_file("line " + std::to_string(doc_.ErrorLineNum()) + ": not valid XML: " + xml_error_text(doc_));
  }
  const XMLElement* root = doc_.RootElement();
  if (!root) msg_.fail_file("the file holds no XML element");
  if (std::strcmp(root->Name(), "COLLADA") != 0)
    msg_.fail(root, "the root element must be <COLLADA>; this is not a COLLADA file");
  index_ids();
}

void Document::index_ids() {
  std::vector<const XMLElement*> stack = {doc_.RootElement()};
  while (!stack.empty()) {
    const XMLElement* e = stack.back();
    stack.pop_back();
    if (const char* id = e->Attribute("id")) ids_.emplace(std::string_view(id), e);  // first one wins
    // Push children in reverse so that document order is visited first.
    std::vector<const XMLElement*> kids;
    for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) kids.push_back(c);
    stack.insert(stack.end(), kids.rbegin(), kids.rend());
  }
}

const XMLElement* Document::find(std::string_view id) const {
  const auto it = ids_.find(id);
  return it == ids_.end() ? nullptr : it->second;
}

const XMLElement* Document::resolve(const XMLElement* from, const char* attr, const char* tag) const {
  const char* url = from->Attribute(attr);
  if (!url) msg_.fail(from, std::string("missing the ") + attr + " attribute");
  if (url[0] != '#')
    msg_.fail(from, std::string(attr) + "=" + quote(url) +
                        " is not a reference into this file (#id); external references are not supported");
  const XMLElement* target = find(std::string_view(url + 1));
  if (!target) msg_.fail(from, std::string(attr) + "=" + quote(url) + " refers to no element in the file");
  if (std::strcmp(target->Name(), tag) != 0)
    msg_.fail(from, std::string(attr) + "=" + quote(url) + " refers to a <" + target->Name() + ">, expected a <" +
                        tag + ">");
  return target;
}

Mat4 Document::up_axis_transform() const {
  const XMLElement* root = doc_.RootElement();
  const XMLElement* asset = root->FirstChildElement("asset");
  if (!asset) msg_.fail(root, "missing <asset><up_axis> (Y_UP, Z_UP or X_UP); the loader does not guess the up axis");
  const XMLElement* up = asset->FirstChildElement("up_axis");
  if (!up) msg_.fail(asset, "missing <up_axis> (Y_UP, Z_UP or X_UP); the loader does not guess the up axis");
  std::string buf;
  const std::string_view v = trim(element_text(up, buf));
  Mat4 m;
  if (v == "Y_UP") {
    // identity
  } else if (v == "Z_UP") {  // (x, y, z) -> (-x, z, y)
    m.m[0][0] = -1; m.m[1][1] = 0; m.m[1][2] = 1; m.m[2][1] = 1; m.m[2][2] = 0;
  } else if (v == "X_UP") {  // (x, y, z) -> (y, x, -z)
    m.m[0][0] = 0; m.m[0][1] = 1; m.m[1][0] = 1; m.m[1][1] = 0; m.m[2][2] = -1;
  } else {
    msg_.fail(up, "unknown up axis " + quote(v) + " (expected Y_UP, Z_UP or X_UP)");
  }
  return m;
}

const XMLElement* Document::visual_scene() {
  const XMLElement* root = doc_.RootElement();
  if (const XMLElement* scene = root->FirstChildElement("scene")) {
    msg_.check_children(scene,
                        {"instance_physics_scene", "instance_visual_scene", "instance_kinematics_scene", "extra"});
    if (const XMLElement* inst = scene->FirstChildElement("instance_visual_scene"))
      return resolve(inst, "url", "visual_scene");
  }
  for (const XMLElement* lib = root->FirstChildElement("library_visual_scenes"); lib;
       lib = lib->NextSiblingElement("library_visual_scenes"))
    if (const XMLElement* vs = lib->FirstChildElement("visual_scene")) return vs;
  msg_.fail(root, "no <visual_scene>: the file describes no scene");
}

const XMLElement* cgl_technique(const XMLElement* owner) {
  for (const XMLElement* extra = owner->FirstChildElement("extra"); extra;
       extra = extra->NextSiblingElement("extra"))
    for (const XMLElement* t = extra->FirstChildElement("technique"); t; t = t->NextSiblingElement("technique")) {
      const char* profile = t->Attribute("profile");
      if (profile && std::strcmp(profile, "CGL") == 0 && t->FirstChildElement()) return t;
    }
  return nullptr;
}

}  // namespace pt::collada
