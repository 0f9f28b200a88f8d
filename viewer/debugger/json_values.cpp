#include "viewer/debugger/json_values.h"

#include <cmath>

namespace pt::debug {

Json json_float(float v) {
  if (std::isnan(v)) return json_text("nan");
  if (std::isinf(v)) return json_text(v > 0 ? "inf" : "-inf");
  return json_real(double(v), "%.9g");
}

Json json_pair(float a, float b) { return json_array({json_float(a), json_float(b)}, true); }

Json json_vec(const Vec3& v) { return json_array({json_float(v.x), json_float(v.y), json_float(v.z)}, true); }

Json json_ray(const Ray& r) {
  return json_object(true)
      .set("origin", json_vec(r.o))
      .set("direction", json_vec(r.d))
      .set("min_t", json_float(r.min_t))
      .set("max_t", json_float(r.max_t))
      .set("depth", json_int(r.depth));
}

Json json_seed(uint64_t seed) { return json_text(std::to_string(seed)); }

Json json_list(std::vector<Json> items) {
  const bool empty = items.empty();
  return json_array(std::move(items), empty);
}

Json json_strings(const std::vector<std::string>& items) {
  std::vector<Json> texts;
  texts.reserve(items.size());
  for (const std::string& s : items) texts.push_back(json_text(s));
  return json_list(std::move(texts));
}

}  // namespace pt::debug
