// COLLADA 1.4 scene loader (with the course's CGL extensions) on tinyxml2.
// The conventions implemented here are documented in docs/scene-format.md.
//
// Structure: the document is parsed once, every element with an id is
// indexed, and the chosen <visual_scene> is walked depth-first in document
// order with the accumulated world transform. Geometry, lights and the camera
// are converted to world space (Y up) as they are met; materials are created
// on first use. The camera is placed last, from the bounds of all geometry.
#include "collada.h"

#include <tinyxml2.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <new>
#include <sstream>
#include <string_view>
#include <system_error>
#include <initializer_list>
#include <unordered_map>
#include <unordered_set>
#include <type_traits>

#include "mat4.h"

namespace pt {

namespace {

using tinyxml2::XMLElement;
using tinyxml2::XMLNode;

constexpr double kPi = 3.14159265358979323846;
constexpr int kMaxNodeDepth = 256;          // nested <node>/<instance_node> levels
constexpr long kMaxInstances = 1000000;     // nodes and instance_* visited: guards against exponential instancing
constexpr int kMaxInputOffset = 4096;       // larger offsets are certainly corrupt

// Defaults used when the scene has no camera (see docs/scene-format.md).
constexpr double kFallbackXfov = 50.0;
constexpr double kFallbackAspect = 4.0 / 3.0;

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

std::string_view trim(std::string_view s) {
  while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
  return s;
}

// Messages are one line: control characters become spaces.
std::string one_line(std::string s) {
  for (char& c : s)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = ' ';
  return s;
}

// Quotes a piece of the input for a message, shortened when long.
std::string quote(std::string_view s) {
  constexpr size_t kMax = 40;
  std::string r = "'";
  if (s.size() > kMax) {
    r.append(s.substr(0, kMax));
    r += "...";
  } else {
    r.append(s);
  }
  return r + "'";
}

std::string fmt(double v) {
  std::ostringstream ss;
  ss.precision(6);
  ss << v;
  return ss.str();
}

std::string fmt(const Vec3d& v) { return "(" + fmt(v.x) + ", " + fmt(v.y) + ", " + fmt(v.z) + ")"; }

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

// ---- Number lists --------------------------------------------------------

// Parses whitespace-separated numbers into `out`. On a token that is not a
// number (or out of the type's range) returns false with the token in `bad`.
template <typename T>
bool parse_list(std::string_view s, std::vector<T>& out, std::string_view* bad) {
  const char* p = s.data();
  const char* end = p + s.size();
  while (true) {
    while (p < end && is_space(*p)) ++p;
    if (p == end) return true;
    const char* tok = p;
    while (p < end && !is_space(*p)) ++p;
    const char* first = tok;
    if (*first == '+' && first + 1 < p && first[1] != '-' && first[1] != '+') ++first;  // xs:double allows '+'
    T v{};
    auto r = std::from_chars(first, p, v);
    if constexpr (std::is_floating_point_v<T>) {
      // Out of double's range: underflow reads as zero, overflow as infinity
      // (which the callers reject where a finite number is needed).
      if (r.ec == std::errc::result_out_of_range && r.ptr == p) {
        const std::string_view t(first, static_cast<size_t>(p - first));
        const bool negative = t.front() == '-';
        const bool tiny = t.find("e-") != t.npos || t.find("E-") != t.npos;
        v = tiny ? (negative ? -0.0 : 0.0) : (negative ? -HUGE_VAL : HUGE_VAL);
        r.ec = std::errc();
      }
    }
    if (r.ec != std::errc() || r.ptr != p) {
      *bad = std::string_view(tok, static_cast<size_t>(p - tok));
      return false;
    }
    out.push_back(v);
  }
}

// Upper bound on how many numbers a text can hold (each needs a character
// and a separator); caps reservations made from count attributes.
size_t max_numbers(std::string_view s) { return s.size() / 2 + 1; }

// ---- The loader ----------------------------------------------------------

struct InstanceMaterial {
  std::string symbol;
  const XMLElement* material;  // the <material> its target names
};

struct PositionData {
  const XMLElement* array = nullptr;  // the <float_array>, for messages
  std::vector<double> xyz;            // 3 per position, in the file's space
  size_t count() const { return xyz.size() / 3; }
};

class Loader {
 public:
  Loader(const std::string& path, std::vector<std::string>* warnings) : path_(path), warnings_(warnings) {}

  Scene run();

 private:
  // Messages.
  std::string describe(const XMLElement* e) const;
  [[noreturn]] void fail(const XMLElement* e, const std::string& what) const;
  [[noreturn]] void fail_file(const std::string& what) const;
  void warn(const XMLElement* e, const std::string& what);
  // A warning about an element itself, given once however often the
  // element is visited (library nodes are visited once per instance).
  void warn_once(const XMLElement* e, const std::string& what);
  // Warns about every child of `parent` whose name is not in `known`: an
  // element the loader does not read where it would read its content (a
  // misspelt <instance_geometry>) would otherwise silently vanish.
  void check_children(const XMLElement* parent, std::initializer_list<std::string_view> known);
  // Fails when the scene would hold more than kMaxScenePrimitives.
  void reserve_primitives(const XMLElement* e, size_t more) const;

  // Text and numbers.
  std::string_view text(const XMLElement* e, std::string& buf) const;
  std::vector<double> numbers(const XMLElement* e) const;
  std::vector<double> numbers(const XMLElement* e, size_t n, const char* what) const;
  double scalar(const XMLElement* e, const char* what) const;
  Vec3d rgb(const XMLElement* e, bool allow_alpha) const;
  bool attr_count(const XMLElement* e, const char* name, uint64_t* out) const;

  // Document structure.
  void read_document();
  void index_ids();
  const XMLElement* resolve(const XMLElement* from, const char* attr, const char* tag) const;
  static const XMLElement* cgl_technique(const XMLElement* owner);
  void read_up_axis();
  const XMLElement* choose_visual_scene();

  // Scene graph.
  Mat4 local_transform(const XMLElement* node);
  void visit_node(const XMLElement* node, const Mat4& parent, int depth);
  void visit_children(const XMLElement* node, const Mat4& world, int depth);

  // Contents.
  void add_geometry(const XMLElement* inst, const Mat4& world);
  void add_mesh(const XMLElement* geom, const XMLElement* mesh, const std::vector<InstanceMaterial>& bound,
                const Mat4& world);
  void add_sphere(const XMLElement* sphere, const std::vector<InstanceMaterial>& bound, const Mat4& world);
  void add_light(const XMLElement* inst, const Mat4& world);
  void add_camera(const XMLElement* inst, const Mat4& world);
  void finish_camera(const XMLElement* vscene);

  // Meshes.
  const PositionData& positions(const XMLElement* source);
  const XMLElement* position_source(const XMLElement* input);
  uint64_t source_count(const XMLElement* source) const;
  void read_primitives(const XMLElement* prim, const XMLElement** pos_source, std::vector<std::array<int, 3>>& tris,
                       std::vector<int>& tri_material, const std::vector<InstanceMaterial>& bound);

  // Materials.
  int material_for(const char* symbol, const std::vector<InstanceMaterial>& bound);
  int default_material();
  Material read_material(const XMLElement* mat);
  void read_cgl_material(const XMLElement* type, Material& m);

  const std::string path_;
  std::vector<std::string>* warnings_;
  tinyxml2::XMLDocument doc_;
  std::unordered_map<std::string_view, const XMLElement*> ids_;
  Mat4 up_map_;
  Scene scene_;

  std::unordered_map<const XMLElement*, PositionData> position_cache_;
  std::unordered_map<const XMLElement*, int> material_index_;
  int default_material_ = -1;

  std::vector<const XMLElement*> instancing_;  // nodes entered through <instance_node>
  long instances_ = 0;                         // nodes and instance_* elements visited
  std::unordered_set<const XMLElement*> warned_;

  // Camera, from the first <instance_camera> met.
  bool have_camera_ = false;
  double xfov_ = 0, yfov_ = 0;
  Vec3d camera_dir_{0, 0, 1};
};

// ---- Messages --------------------------------------------------------------

std::string Loader::describe(const XMLElement* e) const {
  std::string s = "<";
  s += e->Name();
  if (const char* id = e->Attribute("id")) {
    s += " id=\"" + std::string(std::string_view(id).substr(0, 60)) + "\"";
  } else if (const char* profile = e->Attribute("profile")) {
    s += " profile=\"" + std::string(std::string_view(profile).substr(0, 60)) + "\"";
  }
  s += "> (line " + std::to_string(e->GetLineNum()) + ")";
  return s;
}

void Loader::fail(const XMLElement* e, const std::string& what) const {
  throw SceneError(one_line(path_ + ": " + describe(e) + ": " + what));
}

void Loader::fail_file(const std::string& what) const { throw SceneError(one_line(path_ + ": " + what)); }

void Loader::warn(const XMLElement* e, const std::string& what) {
  if (warnings_) warnings_->push_back(one_line(path_ + ": " + describe(e) + ": " + what));
}

void Loader::warn_once(const XMLElement* e, const std::string& what) {
  if (warned_.insert(e).second) warn(e, what);
}

void Loader::check_children(const XMLElement* parent, std::initializer_list<std::string_view> known) {
  for (const XMLElement* c = parent->FirstChildElement(); c; c = c->NextSiblingElement()) {
    const std::string_view name = c->Name();
    if (std::find(known.begin(), known.end(), name) == known.end())
      warn_once(c, "unknown element inside " + describe(parent) + "; it is ignored");
  }
}

void Loader::reserve_primitives(const XMLElement* e, size_t more) const {
  const size_t have = scene_.triangles.size() + scene_.spheres.size();
  if (more > kMaxScenePrimitives - std::min(have, kMaxScenePrimitives))
    fail(e, "the scene would have more than " + std::to_string(kMaxScenePrimitives) +
                " triangles and spheres, the loader's limit (is a node instanced too many times?)");
}

// ---- Text and numbers --------------------------------------------------------

// The character data of `e`. Usually a view of tinyxml2's own string; text
// split by comments or CDATA sections is joined into `buf`.
std::string_view Loader::text(const XMLElement* e, std::string& buf) const {
  const XMLNode* first = e->FirstChild();
  if (!first) return {};
  if (first->ToText() && !first->NextSibling()) return first->Value();
  buf.clear();
  for (const XMLNode* n = first; n; n = n->NextSibling())
    if (n->ToText()) buf += n->Value();
  return buf;
}

std::vector<double> Loader::numbers(const XMLElement* e) const {
  std::string buf;
  const std::string_view s = text(e, buf);
  std::vector<double> v;
  std::string_view bad;
  if (!parse_list(s, v, &bad)) fail(e, quote(bad) + " is not a number");
  return v;
}

// Exactly `n` finite numbers.
std::vector<double> Loader::numbers(const XMLElement* e, size_t n, const char* what) const {
  std::vector<double> v = numbers(e);
  if (v.size() != n)
    fail(e, "expected " + std::to_string(n) + " numbers (" + what + "), found " + std::to_string(v.size()));
  for (double x : v)
    if (!std::isfinite(x)) fail(e, "contains a number that is not finite");
  return v;
}

double Loader::scalar(const XMLElement* e, const char* what) const { return numbers(e, 1, what)[0]; }

// A colour: three finite, non-negative numbers (a fourth, alpha, is allowed
// and ignored where COLLADA writes RGBA).
Vec3d Loader::rgb(const XMLElement* e, bool allow_alpha) const {
  const std::vector<double> v = numbers(e);
  if (v.size() != 3 && !(allow_alpha && v.size() == 4))
    fail(e, std::string("expected ") + (allow_alpha ? "3 or 4 numbers (r g b [a])" : "3 numbers (r g b)") +
                ", found " + std::to_string(v.size()));
  for (size_t i = 0; i < 3; ++i) {
    if (!std::isfinite(v[i])) fail(e, "colour component is not finite");
    if (v[i] < 0) fail(e, "colour component " + fmt(v[i]) + " is negative");
    if (v[i] > std::numeric_limits<float>::max())
      fail(e, "colour component " + fmt(v[i]) + " is too large for single precision");
  }
  return {v[0], v[1], v[2]};
}

// A non-negative integer attribute; false when absent.
bool Loader::attr_count(const XMLElement* e, const char* name, uint64_t* out) const {
  const char* a = e->Attribute(name);
  if (!a) return false;
  const std::string_view s = trim(a);
  uint64_t v = 0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || r.ec != std::errc() || r.ptr != s.data() + s.size())
    fail(e, std::string(name) + "=" + quote(a) + " is not a non-negative integer");
  *out = v;
  return true;
}

// ---- Document structure ---------------------------------------------------------

void Loader::read_document() {
  std::error_code ec;
  if (std::filesystem::is_directory(path_, ec)) fail_file("is a folder, not a scene file");
  std::ifstream in(path_, std::ios::binary);
  if (!in) fail_file(std::string("cannot open file (") + std::strerror(errno) + ")");
  std::ostringstream content;
  content << in.rdbuf();
  if (in.bad()) fail_file("cannot read file");
  const std::string data = content.str();
  if (doc_.Parse(data.data(), data.size()) != tinyxml2::XML_SUCCESS) {
    if (doc_.ErrorID() == tinyxml2::XML_ERROR_EMPTY_DOCUMENT) fail_file("the file is empty or holds no XML element");
    fail_file("line " + std::to_string(doc_.ErrorLineNum()) + ": not valid XML: " + xml_error_text(doc_));
  }
  const XMLElement* root = doc_.RootElement();
  if (!root) fail_file("the file holds no XML element");
  if (std::strcmp(root->Name(), "COLLADA") != 0)
    fail(root, "the root element must be <COLLADA>; this is not a COLLADA file");
}

void Loader::index_ids() {
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

// Follows the "#id" reference in attribute `attr` of `from`, which must name
// an element with tag `tag`.
const XMLElement* Loader::resolve(const XMLElement* from, const char* attr, const char* tag) const {
  const char* url = from->Attribute(attr);
  if (!url) fail(from, std::string("missing the ") + attr + " attribute");
  if (url[0] != '#')
    fail(from, std::string(attr) + "=" + quote(url) +
                   " is not a reference into this file (#id); external references are not supported");
  const auto it = ids_.find(std::string_view(url + 1));
  if (it == ids_.end()) fail(from, std::string(attr) + "=" + quote(url) + " refers to no element in the file");
  if (std::strcmp(it->second->Name(), tag) != 0)
    fail(from, std::string(attr) + "=" + quote(url) + " refers to a <" + it->second->Name() + ">, expected a <" + tag +
                   ">");
  return it->second;
}

// The first <extra><technique profile="CGL"> of `owner` that has content.
const XMLElement* Loader::cgl_technique(const XMLElement* owner) {
  for (const XMLElement* extra = owner->FirstChildElement("extra"); extra;
       extra = extra->NextSiblingElement("extra"))
    for (const XMLElement* t = extra->FirstChildElement("technique"); t; t = t->NextSiblingElement("technique")) {
      const char* profile = t->Attribute("profile");
      if (profile && std::strcmp(profile, "CGL") == 0 && t->FirstChildElement()) return t;
    }
  return nullptr;
}

void Loader::read_up_axis() {
  const XMLElement* root = doc_.RootElement();
  const XMLElement* asset = root->FirstChildElement("asset");
  if (!asset) fail(root, "missing <asset><up_axis> (Y_UP, Z_UP or X_UP); the loader does not guess the up axis");
  const XMLElement* up = asset->FirstChildElement("up_axis");
  if (!up) fail(asset, "missing <up_axis> (Y_UP, Z_UP or X_UP); the loader does not guess the up axis");
  std::string buf;
  const std::string_view v = trim(text(up, buf));
  Mat4 m;
  if (v == "Y_UP") {
    // identity
  } else if (v == "Z_UP") {  // (x, y, z) -> (-x, z, y)
    m.m[0][0] = -1; m.m[1][1] = 0; m.m[1][2] = 1; m.m[2][1] = 1; m.m[2][2] = 0;
  } else if (v == "X_UP") {  // (x, y, z) -> (y, x, -z)
    m.m[0][0] = 0; m.m[0][1] = 1; m.m[1][0] = 1; m.m[1][1] = 0; m.m[2][2] = -1;
  } else {
    fail(up, "unknown up axis " + quote(v) + " (expected Y_UP, Z_UP or X_UP)");
  }
  up_map_ = m;
}

const XMLElement* Loader::choose_visual_scene() {
  const XMLElement* root = doc_.RootElement();
  if (const XMLElement* scene = root->FirstChildElement("scene")) {
    check_children(scene, {"instance_physics_scene", "instance_visual_scene", "instance_kinematics_scene", "extra"});
    if (const XMLElement* inst = scene->FirstChildElement("instance_visual_scene"))
      return resolve(inst, "url", "visual_scene");
  }
  for (const XMLElement* lib = root->FirstChildElement("library_visual_scenes"); lib;
       lib = lib->NextSiblingElement("library_visual_scenes"))
    if (const XMLElement* vs = lib->FirstChildElement("visual_scene")) return vs;
  fail(root, "no <visual_scene>: the file describes no scene");
}

// ---- Scene graph -------------------------------------------------------------

// The node's own transform: its transform elements composed in document
// order, M = T1 * T2 * ... (the last one applies to the geometry first).
Mat4 Loader::local_transform(const XMLElement* node) {
  Mat4 m;
  for (const XMLElement* c = node->FirstChildElement(); c; c = c->NextSiblingElement()) {
    const char* name = c->Name();
    if (std::strcmp(name, "matrix") == 0) {
      std::vector<double> v = numbers(c);
      if (v.size() > 16) fail(c, "expected 16 numbers (a 4x4 matrix, row by row), found " + std::to_string(v.size()));
      for (double x : v)
        if (!std::isfinite(x)) fail(c, "contains a number that is not finite");
      if (v.size() < 16) {
        // The course reads missing numbers as 0 and some of its files rely
        // on it (CBgems.dae's camera has 15). The bottom row cannot be
        // right after such a fill; a transform needs 0 0 0 1 there.
        warn_once(c, "has " + std::to_string(v.size()) +
                         " numbers instead of 16; the missing ones are read as 0, as the course reads them, "
                         "and the bottom row as 0 0 0 1");
        v.resize(16, 0.0);
        v[15] = 1;
      } else if (v[12] != 0 || v[13] != 0 || v[14] != 0 || v[15] != 1) {
        fail(c, "the last row must be 0 0 0 1 (projective transforms are not supported)");
      }
      m = m * Mat4::from_row_major(v.data());
    } else if (std::strcmp(name, "translate") == 0) {
      const std::vector<double> v = numbers(c, 3, "x y z");
      m = m * Mat4::translate({v[0], v[1], v[2]});
    } else if (std::strcmp(name, "scale") == 0) {
      const std::vector<double> v = numbers(c, 3, "x y z");
      m = m * Mat4::scale({v[0], v[1], v[2]});
    } else if (std::strcmp(name, "rotate") == 0) {
      const std::vector<double> v = numbers(c, 4, "axis x y z, angle in degrees");
      const Vec3d axis(v[0], v[1], v[2]);
      if (norm2(axis) == 0) fail(c, "the rotation axis is the zero vector");
      m = m * Mat4::rotate(axis, v[3]);
    } else if (std::strcmp(name, "lookat") == 0) {
      const std::vector<double> v = numbers(c, 9, "eye, interest point and up vector");
      const Vec3d eye(v[0], v[1], v[2]), at(v[3], v[4], v[5]), up(v[6], v[7], v[8]);
      const Vec3d back = eye - at;
      if (norm2(back) == 0) fail(c, "the eye and the interest point are the same point");
      const Vec3d z = normalize(back);
      const Vec3d xc = cross(up, z);
      if (!(norm(xc) > 1e-12 * norm(up))) fail(c, "the up vector is zero or parallel to the view direction");
      const Vec3d x = normalize(xc), y = cross(z, x);
      Mat4 l;
      for (int i = 0; i < 3; ++i) {
        l.m[i][0] = x[i];
        l.m[i][1] = y[i];
        l.m[i][2] = z[i];
        l.m[i][3] = eye[i];
      }
      m = m * l;
    } else if (std::strcmp(name, "skew") == 0) {
      fail(c, "<skew> transforms are not supported");
    }
  }
  return m;
}

void Loader::visit_node(const XMLElement* node, const Mat4& parent, int depth) {
  if (depth > kMaxNodeDepth) fail(node, "nodes are nested more than " + std::to_string(kMaxNodeDepth) + " deep");
  visit_children(node, parent * local_transform(node), depth);
}

// Visits the contents of a node (or of a <visual_scene>) in document order.
void Loader::visit_children(const XMLElement* node, const Mat4& world, int depth) {
  if (std::strcmp(node->Name(), "node") == 0)
    check_children(node, {"asset", "lookat", "matrix", "rotate", "scale", "skew", "translate", "instance_camera",
                          "instance_controller", "instance_geometry", "instance_light", "instance_node", "node",
                          "extra"});
  else
    check_children(node, {"asset", "node", "evaluate_scene", "extra"});
  for (const XMLElement* c = node->FirstChildElement(); c; c = c->NextSiblingElement()) {
    const char* name = c->Name();
    if (std::strncmp(name, "instance_", 9) == 0 || std::strcmp(name, "node") == 0)
      if (++instances_ > kMaxInstances)
        fail(c, "more than " + std::to_string(kMaxInstances) + " nodes and instances; the scene is too large");
    if (std::strcmp(name, "node") == 0) {
      visit_node(c, world, depth + 1);
    } else if (std::strcmp(name, "instance_node") == 0) {
      const XMLElement* target = resolve(c, "url", "node");
      for (const XMLElement* active : instancing_)
        if (active == target) fail(c, "instance_node creates a cycle (the node contains itself)");
      instancing_.push_back(target);
      visit_node(target, world, depth + 1);
      instancing_.pop_back();
    } else if (std::strcmp(name, "instance_geometry") == 0) {
      add_geometry(c, world);
    } else if (std::strcmp(name, "instance_light") == 0) {
      add_light(c, world);
    } else if (std::strcmp(name, "instance_camera") == 0) {
      add_camera(c, world);
    } else if (std::strcmp(name, "instance_controller") == 0) {
      warn(c, "controllers (skinning, morphing) are not supported; skipped");
    }
  }
}

// ---- Geometry ------------------------------------------------------------------

void Loader::add_geometry(const XMLElement* inst, const Mat4& world) {
  const XMLElement* geom = resolve(inst, "url", "geometry");

  std::vector<InstanceMaterial> bound;
  check_children(inst, {"bind_material", "extra"});
  if (const XMLElement* bm = inst->FirstChildElement("bind_material")) {
    check_children(bm, {"param", "technique_common", "technique", "extra"});
    if (const XMLElement* tc = bm->FirstChildElement("technique_common")) {
      check_children(tc, {"instance_material"});
      for (const XMLElement* im = tc->FirstChildElement("instance_material"); im;
           im = im->NextSiblingElement("instance_material")) {
        const char* symbol = im->Attribute("symbol");
        bound.push_back({symbol ? symbol : "", resolve(im, "target", "material")});
      }
    }
  }

  if (const XMLElement* mesh = geom->FirstChildElement("mesh")) {
    add_mesh(geom, mesh, bound, world);
    return;
  }
  if (const XMLElement* t = cgl_technique(geom))
    if (const XMLElement* sphere = t->FirstChildElement("sphere")) {
      add_sphere(sphere, bound, world);
      return;
    }
  warn(geom, "has neither a <mesh> nor a CGL <sphere>; skipped");
}

void Loader::add_sphere(const XMLElement* sphere, const std::vector<InstanceMaterial>& bound, const Mat4& world) {
  check_children(sphere, {"radius"});
  const XMLElement* re = sphere->FirstChildElement("radius");
  if (!re) fail(sphere, "missing <radius>");
  const std::vector<double> v = numbers(re);
  if (v.size() != 1) fail(re, "expected 1 number, found " + std::to_string(v.size()));
  const double r = v[0];
  if (!std::isfinite(r) || r <= 0) fail(re, "the radius must be a positive finite number, not " + fmt(r));
  const Vec3d c = world.point({0, 0, 0});
  const double wr = r * norm(world.vector({1, 0, 0}));
  const Vec3 cf(c);
  const float rf = float(wr);
  if (!is_finite(cf) || !std::isfinite(rf) || !(rf > 0))
    fail(re, "the node transform makes the sphere degenerate (centre " + fmt(c) + ", radius " + fmt(wr) + ")");
  reserve_primitives(sphere, 1);
  Sphere s;
  s.center = cf;
  s.radius = rf;
  s.material = material_for(nullptr, bound);
  scene_.spheres.push_back(s);
}

// Positions of a <source>: its accessor's first three parameters.
const PositionData& Loader::positions(const XMLElement* source) {
  const auto cached = position_cache_.find(source);
  if (cached != position_cache_.end()) return cached->second;

  const XMLElement* tc = source->FirstChildElement("technique_common");
  const XMLElement* acc = tc ? tc->FirstChildElement("accessor") : nullptr;
  if (!acc) fail(source, "missing <technique_common><accessor>");
  const XMLElement* arr = resolve(acc, "source", "float_array");

  std::string buf;
  const std::string_view s = text(arr, buf);
  uint64_t declared = 0;
  const bool has_count = attr_count(arr, "count", &declared);
  std::vector<double> values;
  values.reserve(has_count ? std::min<uint64_t>(declared, max_numbers(s)) : 0);
  std::string_view bad;
  if (!parse_list(s, values, &bad)) fail(arr, quote(bad) + " is not a number");
  if (has_count && values.size() != declared)
    fail(arr, "count=\"" + std::to_string(declared) + "\" but it holds " + std::to_string(values.size()) + " numbers");

  uint64_t count = 0, stride = 1, offset = 0;
  if (!attr_count(acc, "count", &count)) fail(acc, "missing the count attribute");
  attr_count(acc, "stride", &stride);
  attr_count(acc, "offset", &offset);
  if (stride < 3) fail(acc, "positions need stride >= 3, found " + std::to_string(stride));
  if (count > 0) {
    // Overflow-safe form of offset + (count - 1) * stride + 3 <= size.
    const uint64_t n = values.size();
    if (offset > n || 3 > n - offset || (count - 1) > (n - offset - 3) / stride)
      fail(acc, "count=\"" + std::to_string(count) + "\" with stride " + std::to_string(stride) +
                    " reads past the end of " + describe(arr) + ", which holds " + std::to_string(n) + " numbers");
  }

  if (count > uint64_t(std::numeric_limits<int>::max())) fail(acc, "too many positions");
  PositionData d;
  d.array = arr;
  d.xyz.resize(3 * count);
  for (uint64_t i = 0; i < count; ++i) {
    const double* p = &values[offset + i * stride];
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      fail(arr, "position " + std::to_string(i) + " has a coordinate that is not finite (NaN or infinity)");
    d.xyz[3 * i] = p[0];
    d.xyz[3 * i + 1] = p[1];
    d.xyz[3 * i + 2] = p[2];
  }
  return position_cache_.emplace(source, std::move(d)).first->second;
}

// The <source> holding the positions a VERTEX input refers to.
const XMLElement* Loader::position_source(const XMLElement* input) {
  const char* url = input->Attribute("source");
  // VERTEX normally names the mesh's <vertices>; accept a <source> as well.
  if (url && url[0] == '#') {
    const auto it = ids_.find(std::string_view(url + 1));
    if (it != ids_.end() && std::strcmp(it->second->Name(), "source") == 0) return it->second;
  }
  const XMLElement* verts = resolve(input, "source", "vertices");
  for (const XMLElement* in = verts->FirstChildElement("input"); in; in = in->NextSiblingElement("input")) {
    const char* sem = in->Attribute("semantic");
    if (sem && std::strcmp(sem, "POSITION") == 0) return resolve(in, "source", "source");
  }
  fail(verts, "has no <input semantic=\"POSITION\">");
}

// Number of elements of a non-position <source> (for index checks);
// UINT64_MAX when it cannot be told.
uint64_t Loader::source_count(const XMLElement* source) const {
  const XMLElement* tc = source->FirstChildElement("technique_common");
  const XMLElement* acc = tc ? tc->FirstChildElement("accessor") : nullptr;
  uint64_t count = 0;
  if (acc && attr_count(acc, "count", &count)) return count;
  return std::numeric_limits<uint64_t>::max();
}

// Reads one <polylist>, <triangles> or <polygons> into position-index
// triangles (polygons fan-triangulated) with their material.
void Loader::read_primitives(const XMLElement* prim, const XMLElement** pos_source,
                             std::vector<std::array<int, 3>>& tris, std::vector<int>& tri_material,
                             const std::vector<InstanceMaterial>& bound) {
  const std::string_view kind = prim->Name();
  if (kind == "triangles")
    check_children(prim, {"input", "p", "extra"});
  else if (kind == "polylist")
    check_children(prim, {"input", "vcount", "p", "extra"});
  else
    check_children(prim, {"input", "p", "ph", "extra"});

  // Inputs: offset -> the smallest element count among the inputs using it.
  int stride = 0, vertex_offset = -1;
  std::vector<uint64_t> limit;
  const XMLElement* vertex_input = nullptr;
  std::vector<const XMLElement*> limit_source;  // for messages
  for (const XMLElement* in = prim->FirstChildElement("input"); in; in = in->NextSiblingElement("input")) {
    const char* sem = in->Attribute("semantic");
    if (!sem) fail(in, "missing the semantic attribute");
    uint64_t off = 0;
    attr_count(in, "offset", &off);
    if (off > uint64_t(kMaxInputOffset)) fail(in, "offset " + std::to_string(off) + " is too large");
    const int o = int(off);
    if (o + 1 > stride) {
      stride = o + 1;
      limit.resize(size_t(stride), std::numeric_limits<uint64_t>::max());
      limit_source.resize(size_t(stride), nullptr);
    }
    uint64_t n = 0;
    const XMLElement* src = nullptr;
    if (std::strcmp(sem, "VERTEX") == 0) {
      if (vertex_input) fail(in, "a second VERTEX input");
      vertex_input = in;
      vertex_offset = o;
      src = position_source(in);
      if (*pos_source && *pos_source != src)
        fail(in, "refers to other positions than the rest of the mesh; a mesh has one <vertices>");
      *pos_source = src;
      n = positions(src).count();
    } else {
      src = resolve(in, "source", "source");
      n = source_count(src);
    }
    if (n < limit[size_t(o)]) {
      limit[size_t(o)] = n;
      limit_source[size_t(o)] = src;
    }
  }
  if (!vertex_input) fail(prim, "has no <input semantic=\"VERTEX\">");

  uint64_t count = 0;
  const bool has_count = attr_count(prim, "count", &count);
  const int material = material_for(prim->Attribute("material"), bound);

  std::vector<long long> idx;
  std::string buf;
  // Parses one <p> (appending to idx) and returns how many indices it added.
  auto read_p = [&](const XMLElement* p, uint64_t expected = 0) -> size_t {
    const std::string_view s = text(p, buf);
    idx.reserve(idx.size() + size_t(std::min<uint64_t>(expected, max_numbers(s))));
    const size_t before = idx.size();
    std::string_view bad;
    if (!parse_list(s, idx, &bad)) fail(p, quote(bad) + " is not an index");
    return idx.size() - before;
  };
  // Checks the indices [from, to) of idx against their sources.
  auto check = [&](const XMLElement* p, size_t from, size_t to) {
    for (size_t k = from; k < to; ++k) {
      const size_t o = (k - from) % size_t(stride);
      const long long v = idx[k];
      if (v < 0) fail(p, "index " + std::to_string(v) + " (number " + std::to_string(k - from) + " in <p>) is negative");
      if (uint64_t(v) >= limit[o])
        fail(p, "index " + std::to_string(v) + " (number " + std::to_string(k - from) + " in <p>) is out of range for " +
                    describe(limit_source[o]) + ", which has " + std::to_string(limit[o]) + " elements");
    }
  };
  // Fan-triangulates a polygon of n vertices whose indices start at `first`.
  auto emit = [&](size_t first, size_t n) {
    reserve_primitives(prim, tris.size() + (n - 2));
    auto vtx = [&](size_t i) { return int(idx[first + i * size_t(stride) + size_t(vertex_offset)]); };
    const int v0 = vtx(0);
    for (size_t i = 1; i + 1 < n; ++i) {
      tris.push_back({v0, vtx(i), vtx(i + 1)});
      tri_material.push_back(material);
    }
  };

  if (kind == "triangles") {
    const XMLElement* p = prim->FirstChildElement("p");
    if (!p) {
      if (has_count && count > 0) fail(prim, "missing <p>");
      return;
    }
    const size_t per_tri = 3 * size_t(stride);
    const size_t n = read_p(p, has_count && count < (uint64_t(1) << 40) ? count * per_tri : 0);
    if (has_count && (n % per_tri != 0 || n / per_tri != count))
      fail(p, "has " + std::to_string(n) + " indices; count=\"" + std::to_string(count) + "\" with " +
                  std::to_string(stride) + " per vertex needs " + std::to_string(count * per_tri));
    if (n % per_tri != 0)
      fail(p, "has " + std::to_string(n) + " indices, not a multiple of " + std::to_string(per_tri) +
                  " (3 vertices of " + std::to_string(stride) + " indices)");
    check(p, 0, n);
    for (size_t t = 0; t < n / per_tri; ++t) emit(t * per_tri, 3);
  } else if (kind == "polylist") {
    const XMLElement* vc = prim->FirstChildElement("vcount");
    const XMLElement* p = prim->FirstChildElement("p");
    if (!vc && !p && (!has_count || count == 0)) return;  // an empty list
    if (!vc) fail(prim, "missing <vcount>");
    if (!p) fail(prim, "missing <p>");
    std::vector<long long> counts;
    {
      std::string vbuf;
      std::string_view bad;
      if (!parse_list(text(vc, vbuf), counts, &bad)) fail(vc, quote(bad) + " is not a vertex count");
    }
    if (has_count && counts.size() != count)
      fail(vc, "lists " + std::to_string(counts.size()) + " polygons but count=\"" + std::to_string(count) + "\"");
    uint64_t needed = 0;
    for (size_t i = 0; i < counts.size(); ++i) {
      if (counts[i] < 3)
        fail(vc, "polygon " + std::to_string(i) + " has " + std::to_string(counts[i]) +
                     " vertices; a polygon needs at least 3");
      if (uint64_t(counts[i]) > (uint64_t(1) << 40)) fail(vc, "polygon " + std::to_string(i) + " is impossibly large");
      needed += uint64_t(counts[i]) * uint64_t(stride);
      if (needed > (uint64_t(1) << 62)) fail(vc, "the polygons are impossibly large");
    }
    const size_t n = read_p(p, needed);
    if (n != needed)
      fail(p, "has " + std::to_string(n) + " indices but <vcount> with " + std::to_string(stride) +
                  " per vertex needs " + std::to_string(needed));
    check(p, 0, n);
    size_t first = 0;
    for (long long c : counts) {
      emit(first, size_t(c));
      first += size_t(c) * size_t(stride);
    }
  } else {  // polygons: one <p> per polygon; <ph> is a polygon with holes
    uint64_t polys = 0;
    for (const XMLElement* c = prim->FirstChildElement(); c; c = c->NextSiblingElement()) {
      const XMLElement* p = nullptr;
      if (std::strcmp(c->Name(), "p") == 0) {
        p = c;
      } else if (std::strcmp(c->Name(), "ph") == 0) {
        p = c->FirstChildElement("p");
        if (!p) fail(c, "missing <p>");
        warn(c, "holes (<h>) are not supported; the polygon is filled");
      } else {
        continue;
      }
      ++polys;
      idx.clear();
      const size_t n = read_p(p);
      if (n % size_t(stride) != 0)
        fail(p, "has " + std::to_string(n) + " indices, not a multiple of " + std::to_string(stride) +
                    " (indices per vertex)");
      if (n / size_t(stride) < 3)
        fail(p, "the polygon has " + std::to_string(n / size_t(stride)) + " vertices; a polygon needs at least 3");
      check(p, 0, n);
      emit(0, n / size_t(stride));
    }
    if (has_count && polys != count)
      fail(prim, "holds " + std::to_string(polys) + " polygons but count=\"" + std::to_string(count) + "\"");
  }
}

// Whether every vertex used by a non-degenerate triangle lies on a
// boundary edge (an edge of exactly one triangle).
static bool all_vertices_on_boundary(const std::vector<std::array<int, 3>>& tris,
                                     const std::vector<Vec3d>& face) {
  std::vector<uint64_t> edges;
  edges.reserve(3 * tris.size());
  for (size_t t = 0; t < tris.size(); ++t) {
    if (norm2(face[t]) == 0) continue;
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = uint32_t(tris[t][size_t(k)]), b = uint32_t(tris[t][size_t((k + 1) % 3)]);
      edges.push_back((uint64_t(std::min(a, b)) << 32) | std::max(a, b));
    }
  }
  if (edges.empty()) return false;
  std::sort(edges.begin(), edges.end());
  std::vector<uint32_t> used, on_boundary;
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    const uint32_t a = uint32_t(edges[i] >> 32), b = uint32_t(edges[i]);
    used.push_back(a);
    used.push_back(b);
    if (j - i == 1) {
      on_boundary.push_back(a);
      on_boundary.push_back(b);
    }
    i = j;
  }
  for (auto* v : {&used, &on_boundary}) {
    std::sort(v->begin(), v->end());
    v->erase(std::unique(v->begin(), v->end()), v->end());
  }
  return used.size() == on_boundary.size();
}

void Loader::add_mesh(const XMLElement* geom, const XMLElement* mesh, const std::vector<InstanceMaterial>& bound,
                      const Mat4& world) {
  const XMLElement* pos_source = nullptr;
  std::vector<std::array<int, 3>> tris;
  std::vector<int> tri_material;
  check_children(mesh, {"source", "vertices", "lines", "linestrips", "polygons", "polylist", "triangles", "trifans",
                        "tristrips", "extra"});
  for (const XMLElement* c = mesh->FirstChildElement(); c; c = c->NextSiblingElement()) {
    const char* name = c->Name();
    if (std::strcmp(name, "polylist") == 0 || std::strcmp(name, "triangles") == 0 ||
        std::strcmp(name, "polygons") == 0) {
      read_primitives(c, &pos_source, tris, tri_material, bound);
    } else if (std::strcmp(name, "lines") == 0 || std::strcmp(name, "linestrips") == 0 ||
               std::strcmp(name, "tristrips") == 0 || std::strcmp(name, "trifans") == 0) {
      warn(c, std::string("<") + name + "> primitives are not supported; skipped");
    }
  }
  if (tris.empty()) return;

  // Only the positions the triangles use are transformed, renumbered in
  // order: an instance costs its triangles, not the whole position array
  // (which matters when a large array is instanced many times).
  const PositionData& pd = positions(pos_source);
  std::vector<int> used;  // file position index of each renumbered one
  if (pd.count() <= 12 * tris.size()) {
    std::vector<int> number(pd.count(), -1);
    for (const auto& t : tris)
      for (int v : t) number[size_t(v)] = 0;
    for (size_t i = 0; i < number.size(); ++i)
      if (number[i] == 0) {
        number[i] = int(used.size());
        used.push_back(int(i));
      }
    for (auto& t : tris)
      for (int& v : t) v = number[size_t(v)];
  } else {
    used.reserve(3 * tris.size());
    for (const auto& t : tris) used.insert(used.end(), t.begin(), t.end());
    std::sort(used.begin(), used.end());
    used.erase(std::unique(used.begin(), used.end()), used.end());
    for (auto& t : tris)
      for (int& v : t) v = int(std::lower_bound(used.begin(), used.end(), v) - used.begin());
  }
  // World-space positions, stored in float as the renderer will see them.
  std::vector<Vec3> wp(used.size());
  for (size_t j = 0; j < used.size(); ++j) {
    const size_t i = size_t(used[j]);
    const Vec3d p = world.point({pd.xyz[3 * i], pd.xyz[3 * i + 1], pd.xyz[3 * i + 2]});
    const Vec3 f(p);
    if (!is_finite(f))
      fail(pd.array, "position " + std::to_string(i) + " is not finite after the node transform " + fmt(p));
    wp[j] = f;
  }

  // Smooth normals: per position, the sum of the (area-weighted) cross
  // products of the triangles using it. Zero-area triangles are dropped.
  std::vector<Vec3d> acc(wp.size(), Vec3d(0.0));
  std::vector<Vec3d> face(tris.size());
  size_t degenerate = 0;
  for (size_t t = 0; t < tris.size(); ++t) {
    const Vec3d a(wp[size_t(tris[t][0])]), b(wp[size_t(tris[t][1])]), c(wp[size_t(tris[t][2])]);
    const Vec3d n = cross(b - a, c - a);
    face[t] = n;
    if (norm2(n) == 0) {
      ++degenerate;
      continue;
    }
    for (int k = 0; k < 3; ++k) acc[size_t(tris[t][size_t(k)])] += n;
  }
  // The course's half-edge code gives every vertex on a mesh boundary the
  // reversed normal. For meshes made only of boundary vertices (single
  // quads and polygons: the Cornell box walls, the light quad, plane.dae)
  // that reverses the whole surface, and the course's scene files are
  // authored for it: their walls face into the box only this way. Larger
  // open meshes keep their winding (reversing just their boundary ring,
  // as the course does, flips normals across a triangle).
  const double orient = all_vertices_on_boundary(tris, face) ? -1.0 : 1.0;

  // Within the limit (read_primitives checked it), and never reserving past it.
  const size_t needed = scene_.triangles.size() + tris.size() - degenerate;
  if (needed > scene_.triangles.capacity())
    scene_.triangles.reserve(std::min(std::max(needed, 2 * scene_.triangles.capacity()), kMaxScenePrimitives));
  for (size_t t = 0; t < tris.size(); ++t) {
    if (norm2(face[t]) == 0) continue;
    const Vec3d fn = normalize(face[t]) * orient;
    Vec3 n[3];
    for (int k = 0; k < 3; ++k) {
      const Vec3d s = acc[size_t(tris[t][size_t(k)])];
      // Opposite faces sharing a vertex can cancel; fall back to the face.
      const double len = norm(s);
      n[k] = Vec3(len > 0 && std::isfinite(len) ? s * (orient / len) : fn);
    }
    Triangle tri;
    tri.p1 = wp[size_t(tris[t][0])];
    tri.p2 = wp[size_t(tris[t][1])];
    tri.p3 = wp[size_t(tris[t][2])];
    tri.n1 = n[0];
    tri.n2 = n[1];
    tri.n3 = n[2];
    tri.material = tri_material[t];
    scene_.triangles.push_back(tri);
  }
  if (degenerate > 0)
    warn(geom, "dropped " + std::to_string(degenerate) + " degenerate (zero-area) triangle" +
                   (degenerate == 1 ? "" : "s"));
}

// ---- Materials -----------------------------------------------------------------

int Loader::default_material() {
  if (default_material_ < 0) {
    Material m;
    m.name = "default";
    m.type = MaterialType::Diffuse;
    m.albedo = Color(0.5f);
    default_material_ = int(scene_.materials.size());
    scene_.materials.push_back(m);
  }
  return default_material_;
}

// The material of a primitive list with material="symbol" (nullptr for
// none): the bound instance_material with that symbol, else the first one,
// else the default material.
int Loader::material_for(const char* symbol, const std::vector<InstanceMaterial>& bound) {
  if (bound.empty()) return default_material();
  const InstanceMaterial* chosen = &bound.front();
  if (symbol)
    for (const InstanceMaterial& b : bound)
      if (b.symbol == symbol) {
        chosen = &b;
        break;
      }
  const auto it = material_index_.find(chosen->material);
  if (it != material_index_.end()) return it->second;
  Material m = read_material(chosen->material);
  const int i = int(scene_.materials.size());
  scene_.materials.push_back(std::move(m));
  material_index_.emplace(chosen->material, i);
  return i;
}

void Loader::read_cgl_material(const XMLElement* type, Material& m) {
  auto color = [&](const char* name, Color& out) {
    if (const XMLElement* e = type->FirstChildElement(name)) out = Color(rgb(e, false));
  };
  auto number = [&](const char* name, float& out, double lo, bool lo_inclusive) {
    if (const XMLElement* e = type->FirstChildElement(name)) {
      const double v = scalar(e, name);
      if (lo_inclusive ? v < lo : v <= lo)
        fail(e, std::string("must be ") + (lo_inclusive ? ">= " : "> ") + fmt(lo) + ", found " + fmt(v));
      if (v > std::numeric_limits<float>::max()) fail(e, fmt(v) + " is too large for single precision");
      out = float(v);
    }
  };
  const std::string_view t = type->Name();
  if (t == "emission")
    check_children(type, {"radiance"});
  else if (t == "mirror")
    check_children(type, {"reflectance"});
  else if (t == "glass")
    check_children(type, {"reflectance", "transmittance", "roughness", "ior"});
  else if (t == "refraction")
    check_children(type, {"transmittance", "roughness", "ior"});
  else if (t == "microfacet")
    check_children(type, {"alpha", "eta", "k"});
  if (t == "emission") {
    m.type = MaterialType::Emission;
    m.albedo = Color(0.0f);
    color("radiance", m.emission);
  } else if (t == "mirror") {
    m.type = MaterialType::Mirror;
    color("reflectance", m.reflectance);
  } else if (t == "glass") {
    m.type = MaterialType::Glass;
    color("reflectance", m.reflectance);
    color("transmittance", m.transmittance);
    number("roughness", m.roughness, 0.0, true);
    number("ior", m.ior, 0.0, false);
  } else if (t == "refraction") {
    m.type = MaterialType::Refraction;
    color("transmittance", m.transmittance);
    number("roughness", m.roughness, 0.0, true);
    number("ior", m.ior, 0.0, false);
  } else if (t == "microfacet") {
    m.type = MaterialType::Microfacet;
    number("alpha", m.alpha, 0.0, false);
    color("eta", m.eta);
    color("k", m.k);
  }
}

Material Loader::read_material(const XMLElement* mat) {
  Material m;
  m.name = mat->Attribute("id") ? mat->Attribute("id") : "";
  const XMLElement* ie = mat->FirstChildElement("instance_effect");
  if (!ie) fail(mat, "missing <instance_effect>");
  const XMLElement* effect = resolve(ie, "url", "effect");

  if (const XMLElement* t = cgl_technique(effect)) {
    const XMLElement* type = t->FirstChildElement();
    static const char* const known[] = {"emission", "mirror", "glass", "refraction", "microfacet"};
    for (const char* k : known)
      if (std::strcmp(type->Name(), k) == 0) {
        read_cgl_material(type, m);
        return m;
      }
    warn(type, "unknown CGL material type; using the effect's diffuse colour");
  }

  // profile_COMMON: the diffuse colour of the first shading model.
  if (const XMLElement* prof = effect->FirstChildElement("profile_COMMON"))
    if (const XMLElement* tech = prof->FirstChildElement("technique")) {
      check_children(tech, {"asset", "image", "newparam", "constant", "lambert", "phong", "blinn", "extra"});
      for (const XMLElement* model = tech->FirstChildElement(); model; model = model->NextSiblingElement()) {
        const char* name = model->Name();
        if (std::strcmp(name, "phong") && std::strcmp(name, "lambert") && std::strcmp(name, "blinn") &&
            std::strcmp(name, "constant"))
          continue;
        check_children(model, {"emission", "ambient", "diffuse", "specular", "shininess", "reflective",
                               "reflectivity", "transparent", "transparency", "index_of_refraction"});
        if (const XMLElement* diffuse = model->FirstChildElement("diffuse")) {
          if (const XMLElement* c = diffuse->FirstChildElement("color"))
            m.albedo = Color(rgb(c, true));
          else
            warn(diffuse, "only a <color> is supported (textures are not); using diffuse 0.5");
        }
        break;
      }
    }
  return m;
}

// ---- Lights ----------------------------------------------------------------------

void Loader::add_light(const XMLElement* inst, const Mat4& world) {
  const XMLElement* light = resolve(inst, "url", "light");
  const XMLElement* tech = cgl_technique(light);
  if (!tech) tech = light->FirstChildElement("technique_common");
  const XMLElement* type = tech ? tech->FirstChildElement() : nullptr;
  if (!type) {
    warn(light, "has no light type under <technique_common> or a CGL technique; skipped");
    return;
  }
  const std::string_view t = type->Name();
  if (t == "spot") {
    warn(light, "spot lights are not supported; skipped");
    return;
  }
  if (t != "area" && t != "point" && t != "directional" && t != "ambient") {
    warn(light, "unknown light type <" + std::string(t) + ">; skipped");
    return;
  }

  if (t == "point")
    check_children(type, {"color", "constant_attenuation", "linear_attenuation", "quadratic_attenuation"});
  else
    check_children(type, {"color"});
  const XMLElement* ce = type->FirstChildElement("color");
  if (!ce) fail(type, "missing <color>");
  Light l;
  l.radiance = Color(rgb(ce, false));

  const Vec3d c = world.point({0, 0, 0});
  if (t == "area") {
    l.type = LightType::Area;
    const Vec3d dx = world.point({-1, 0, 0}) - c, dy = world.point({0, 1, 0}) - c;
    const Vec3d d = world.point({0, 0, -1}) - c;
    if (norm2(cross(dx, dy)) == 0 || norm2(d) == 0)
      fail(inst, "the node transform makes the area light degenerate (zero area or no direction)");
    l.position = Vec3(c);
    l.dim_x = Vec3(dx);
    l.dim_y = Vec3(dy);
    l.direction = Vec3(normalize(d));
  } else if (t == "point") {
    l.type = LightType::Point;
    l.position = Vec3(c);
    auto atten = [&](const char* name, float& out) {
      if (const XMLElement* e = type->FirstChildElement(name)) {
        const double v = scalar(e, name);
        if (v < 0) fail(e, "attenuation must not be negative, found " + fmt(v));
        if (v > std::numeric_limits<float>::max()) fail(e, fmt(v) + " is too large for single precision");
        out = float(v);
      }
    };
    atten("constant_attenuation", l.constant_attenuation);
    atten("linear_attenuation", l.linear_attenuation);
    atten("quadratic_attenuation", l.quadratic_attenuation);
    if (l.constant_attenuation == 0 && l.linear_attenuation == 0 && l.quadratic_attenuation == 0)
      fail(type, "all attenuation coefficients are zero (the intensity would be infinite)");
  } else if (t == "directional") {
    l.type = LightType::Directional;
    const Vec3d d = world.vector({0, 0, -1});  // rotation (linear part) only
    if (norm2(d) == 0) fail(inst, "the node transform gives the directional light no direction");
    l.direction = Vec3(normalize(d));
  } else {
    l.type = LightType::Ambient;
  }
  if (!is_finite(l.position) || !is_finite(l.direction) || !is_finite(l.dim_x) || !is_finite(l.dim_y))
    fail(inst, "the node transform puts the light at a non-finite place");
  scene_.lights.push_back(l);
}

// ---- Camera ----------------------------------------------------------------------

void Loader::add_camera(const XMLElement* inst, const Mat4& world) {
  const XMLElement* cam = resolve(inst, "url", "camera");
  if (have_camera_) return;  // the first camera met is the scene's camera
  have_camera_ = true;

  const XMLElement* optics = cam->FirstChildElement("optics");
  const XMLElement* tc = optics ? optics->FirstChildElement("technique_common") : nullptr;
  const XMLElement* persp = tc ? tc->FirstChildElement("perspective") : nullptr;

  double xfov = 0, yfov = 0, aspect = 0;
  bool has_x = false, has_y = false, has_aspect = false;
  if (!persp) {
    warn(cam, "not a perspective camera; using a " + fmt(kFallbackXfov) + " degree horizontal field of view");
  } else {
    check_children(persp, {"xfov", "yfov", "aspect_ratio", "znear", "zfar"});
    auto read = [&](const char* name, double& out) {
      const XMLElement* e = persp->FirstChildElement(name);
      if (!e) return false;
      out = scalar(e, name);
      return true;
    };
    if ((has_x = read("xfov", xfov)) && !(xfov > 0 && xfov < 180))
      fail(persp->FirstChildElement("xfov"), "the field of view must be in (0, 180) degrees, found " + fmt(xfov));
    if ((has_y = read("yfov", yfov)) && !(yfov > 0 && yfov < 180))
      fail(persp->FirstChildElement("yfov"), "the field of view must be in (0, 180) degrees, found " + fmt(yfov));
    if ((has_aspect = read("aspect_ratio", aspect)) && !(aspect > 0))
      fail(persp->FirstChildElement("aspect_ratio"), "the aspect ratio must be positive, found " + fmt(aspect));
    double znear = 0.001, zfar = 1000.0;
    read("znear", znear);
    read("zfar", zfar);
    if (!(znear >= 0) || !(zfar > znear))
      fail(persp, "needs 0 <= znear < zfar, found znear " + fmt(znear) + ", zfar " + fmt(zfar));
    scene_.camera.near_clip = znear;
    scene_.camera.far_clip = zfar;
    if (!has_x && !has_y) fail(persp, "needs <xfov> or <yfov>");
  }
  if (!has_x && !has_y) {
    xfov = kFallbackXfov;
    has_x = true;
  }
  if (!has_aspect) aspect = kFallbackAspect;
  auto other = [&](double fov, double ratio) {
    return 2.0 * std::atan(std::tan(fov * kPi / 360.0) * ratio) * 180.0 / kPi;
  };
  if (has_x && !has_y) yfov = other(xfov, 1.0 / aspect);
  if (has_y && !has_x) xfov = other(yfov, aspect);
  // An extreme aspect ratio (or field of view) leaves a frame of no width
  // or of 180 degrees, which no image can show.
  Camera fitted;
  fitted.fit_course_frame(xfov, yfov);
  if (!(xfov > 0 && xfov < 180 && yfov > 0 && yfov < 180) || !std::isfinite(fitted.screen_dist) ||
      !(fitted.screen_dist > 0) || !(fitted.hfov_deg > 0 && fitted.hfov_deg < 180) ||
      !(fitted.vfov_deg > 0 && fitted.vfov_deg < 180))
    fail(persp ? persp : cam, "the field of view " + fmt(xfov) + " x " + fmt(yfov) +
                           " degrees (from xfov, yfov and aspect_ratio) is too narrow or too wide to render");
  xfov_ = xfov;
  yfov_ = yfov;

  // The course's rule: the direction from the origin to the point one unit
  // in front of the camera (see docs/scene-format.md).
  const Vec3d ahead = world.point({0, 0, -1});
  if (!is_finite(ahead) || norm2(ahead) == 0) {
    warn(inst, "the point in front of the camera is the origin; viewing along -Z instead");
    camera_dir_ = Vec3d(0, 0, 1);
  } else {
    camera_dir_ = normalize(ahead);
  }
}

void Loader::finish_camera(const XMLElement* vscene) {
  if (!have_camera_) {
    warn(vscene, "no camera in the scene; looking along -Z with a " + fmt(kFallbackXfov) +
                     " degree horizontal field of view");
    xfov_ = kFallbackXfov;
    yfov_ = 2.0 * std::atan(std::tan(kFallbackXfov * kPi / 360.0) / kFallbackAspect) * 180.0 / kPi;
    camera_dir_ = Vec3d(0, 0, 1);
  }
  // The renderer works in float: a scene whose bounds overflow it (a huge
  // sphere radius or scale) would put the camera at infinity.
  const BBox bounds = scene_.bounds();
  const Vec3 lo = bounds.lo, hi = bounds.hi;
  if (!is_finite(lo) || !is_finite(hi) || !is_finite(bounds.extent()) || !is_finite(bounds.centroid()))
    fail(vscene, "the scene is too large for single-precision numbers: its bounds reach " + fmt(Vec3d(lo)) + " to " +
                     fmt(Vec3d(hi)));
  scene_.camera.fit_course_frame(xfov_, yfov_);
  scene_.camera.place_course(camera_dir_, bounds);
  if (!is_finite(Vec3(scene_.camera.position)))
    fail(vscene, "the scene is too large for single-precision numbers: the camera would stand at " +
                     fmt(scene_.camera.position));
}

// ---- Driver ----------------------------------------------------------------------

Scene Loader::run() {
  read_document();
  index_ids();
  read_up_axis();
  const XMLElement* vscene = choose_visual_scene();
  scene_.source = path_;
  visit_children(vscene, up_map_, 0);
  if (scene_.triangles.empty() && scene_.spheres.empty()) fail(vscene, "no triangles or spheres in the scene");
  finish_camera(vscene);
  return std::move(scene_);
}

}  // namespace

Scene load_collada(const std::string& path, std::vector<std::string>* warnings) {
  try {
    Loader loader(path, warnings);
    return loader.run();
  } catch (const SceneError&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw SceneError(path + ": out of memory while loading the scene");
  } catch (const std::exception& e) {
    throw SceneError(one_line(path + ": " + e.what()));
  }
}

}  // namespace pt
