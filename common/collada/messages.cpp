// The loader's errors and warnings (see messages.h).
#include "common/collada/messages.h"

#include <algorithm>
#include <sstream>

#include "common/collada.h"

namespace pt::collada {

std::string one_line(std::string s) {
  for (char& c : s)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = ' ';
  return s;
}

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

std::string Messages::describe(const XMLElement* e) const {
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

void Messages::fail(const XMLElement* e, const std::string& what) const {
  throw SceneError(one_line(path_ + ": " + describe(e) + ": " + what));
}

void Messages::fail_file(const std::string& what) const { throw SceneError(one_line(path_ + ": " + what)); }

void Messages::warn(const XMLElement* e, const std::string& what) {
  if (warnings_) warnings_->push_back(one_line(path_ + ": " + describe(e) + ": " + what));
}

void Messages::warn_once(const XMLElement* e, const std::string& what) {
  if (warned_.insert(e).second) warn(e, what);
}

void Messages::check_children(const XMLElement* parent, std::initializer_list<std::string_view> known) {
  for (const XMLElement* c = parent->FirstChildElement(); c; c = c->NextSiblingElement()) {
    const std::string_view name = c->Name();
    if (std::find(known.begin(), known.end(), name) == known.end())
      warn_once(c, "unknown element inside " + describe(parent) + "; it is ignored");
  }
}

}  // namespace pt::collada
