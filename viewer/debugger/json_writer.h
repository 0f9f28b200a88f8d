// Small JSON builders for the debugger's results (strings go through the
// project's json_quote). Floats are written with 9 significant digits, which
// read back as the same float; NaN and infinities, which JSON cannot hold,
// are written as the strings "nan", "inf" and "-inf" so that the page can
// show them.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "ray.h"

namespace pt::debug {

std::string json_number(double v);
std::string json_float(float v);
std::string json_vec(const Vec3& v);
std::string json_ray(const Ray& r);
std::string json_strings(const std::vector<std::string>& items);
// [a, b, c] from already written JSON values.
std::string json_array(const std::vector<std::string>& items);

// {"key": value, ...} in the order added.
class JsonObject {
 public:
  JsonObject& raw(const std::string& key, const std::string& json);
  JsonObject& str(const std::string& key, const std::string& text);
  JsonObject& num(const std::string& key, double v);
  JsonObject& flt(const std::string& key, float v);
  JsonObject& integer(const std::string& key, long long v);
  JsonObject& uint(const std::string& key, uint64_t v);
  JsonObject& boolean(const std::string& key, bool v);
  JsonObject& vec(const std::string& key, const Vec3& v) { return raw(key, json_vec(v)); }
  JsonObject& ray(const std::string& key, const Ray& r) { return raw(key, json_ray(r)); }
  std::string text() const { return body_.empty() ? "{}" : "{" + body_ + "}"; }

 private:
  std::string body_;
};

}  // namespace pt::debug
