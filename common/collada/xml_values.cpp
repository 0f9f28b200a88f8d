// Values written as XML text (see xml_values.h).
#include "common/collada/xml_values.h"

#include <limits>

namespace pt::collada {

using tinyxml2::XMLNode;

std::string_view trim(std::string_view s) {
  while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
  return s;
}

std::string_view element_text(const XMLElement* e, std::string& buf) {
  const XMLNode* first = e->FirstChild();
  if (!first) return {};
  if (first->ToText() && !first->NextSibling()) return first->Value();
  buf.clear();
  for (const XMLNode* n = first; n; n = n->NextSibling())
    if (n->ToText()) buf += n->Value();
  return buf;
}

std::vector<double> numbers(const Messages& msg, const XMLElement* e) {
  std::string buf;
  const std::string_view s = element_text(e, buf);
  std::vector<double> v;
  std::string_view bad;
  if (!parse_list(s, v, &bad)) msg.fail(e, quote(bad) + " is not a number");
  return v;
}

std::vector<double> numbers(const Messages& msg, const XMLElement* e, size_t n, const char* what) {
  std::vector<double> v = numbers(msg, e);
  if (v.size() != n)
    msg.fail(e, "expected " + std::to_string(n) + " numbers (" + what + "), found " + std::to_string(v.size()));
  for (double x : v)
    if (!std::isfinite(x)) msg.fail(e, "contains a number that is not finite");
  return v;
}

double scalar(const Messages& msg, const XMLElement* e, const char* what) { return numbers(msg, e, 1, what)[0]; }

Vec3d rgb(const Messages& msg, const XMLElement* e, bool allow_alpha) {
  const std::vector<double> v = numbers(msg, e);
  if (v.size() != 3 && !(allow_alpha && v.size() == 4))
    msg.fail(e, std::string("expected ") + (allow_alpha ? "3 or 4 numbers (r g b [a])" : "3 numbers (r g b)") +
                    ", found " + std::to_string(v.size()));
  for (size_t i = 0; i < 3; ++i) {
    if (!std::isfinite(v[i])) msg.fail(e, "colour component is not finite");
    if (v[i] < 0) msg.fail(e, "colour component " + fmt(v[i]) + " is negative");
    if (v[i] > std::numeric_limits<float>::max())
      msg.fail(e, "colour component " + fmt(v[i]) + " is too large for single precision");
  }
  return {v[0], v[1], v[2]};
}

bool count_attribute(const Messages& msg, const XMLElement* e, const char* name, uint64_t* out) {
  const char* a = e->Attribute(name);
  if (!a) return false;
  const std::string_view s = trim(a);
  uint64_t v = 0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || r.ec != std::errc() || r.ptr != s.data() + s.size())
    msg.fail(e, std::string(name) + "=" + quote(a) + " is not a non-negative integer");
  *out = v;
  return true;
}

}  // namespace pt::collada
