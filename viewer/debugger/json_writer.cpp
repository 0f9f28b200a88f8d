#include "json_writer.h"

#include <cmath>
#include <cstdio>

#include "json.h"

namespace pt::debug {

namespace {
std::string non_finite(double v) {
  if (std::isnan(v)) return "\"nan\"";
  return v > 0 ? "\"inf\"" : "\"-inf\"";
}
}  // namespace

std::string json_number(double v) {
  if (!std::isfinite(v)) return non_finite(v);
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string json_float(float v) {
  if (!std::isfinite(v)) return non_finite(v);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", double(v));
  return buf;
}

std::string json_vec(const Vec3& v) {
  return "[" + json_float(v.x) + ", " + json_float(v.y) + ", " + json_float(v.z) + "]";
}

std::string json_ray(const Ray& r) {
  return JsonObject()
      .vec("origin", r.o)
      .vec("direction", r.d)
      .flt("min_t", r.min_t)
      .flt("max_t", r.max_t)
      .integer("depth", r.depth)
      .text();
}

std::string json_array(const std::vector<std::string>& items) {
  std::string out = "[";
  for (size_t i = 0; i < items.size(); ++i) out += (i ? ", " : "") + items[i];
  return out + "]";
}

std::string json_strings(const std::vector<std::string>& items) {
  std::vector<std::string> quoted;
  quoted.reserve(items.size());
  for (const std::string& s : items) quoted.push_back(json_quote(s));
  return json_array(quoted);
}

JsonObject& JsonObject::raw(const std::string& key, const std::string& json) {
  if (!body_.empty()) body_ += ", ";
  body_ += json_quote(key) + ": " + json;
  return *this;
}
JsonObject& JsonObject::str(const std::string& key, const std::string& text) { return raw(key, json_quote(text)); }
JsonObject& JsonObject::num(const std::string& key, double v) { return raw(key, json_number(v)); }
JsonObject& JsonObject::flt(const std::string& key, float v) { return raw(key, json_float(v)); }
JsonObject& JsonObject::integer(const std::string& key, long long v) { return raw(key, std::to_string(v)); }
JsonObject& JsonObject::uint(const std::string& key, uint64_t v) { return raw(key, std::to_string(v)); }
JsonObject& JsonObject::boolean(const std::string& key, bool v) { return raw(key, v ? "true" : "false"); }

}  // namespace pt::debug
