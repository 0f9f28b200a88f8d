// The debugger's JSON read back as the page reads it (the rules of
// viewer/debugger/json_values.h): a float is a number or "nan", "inf",
// "-inf"; a vector or colour is three of them. Throws on anything else.
// For the debugger's tests (tests/debugger).
#pragma once
#include <limits>
#include <stdexcept>
#include <string>

#include "common/json.h"
#include "common/vec3.h"

namespace pt {

inline float read_float(const Json* v) {
  if (v == nullptr) throw std::runtime_error("missing float");
  if (v->type == Json::Type::String) {
    if (v->string == "nan") return std::numeric_limits<float>::quiet_NaN();
    if (v->string == "inf") return std::numeric_limits<float>::infinity();
    if (v->string == "-inf") return -std::numeric_limits<float>::infinity();
    throw std::runtime_error("not a float: \"" + v->string + "\"");
  }
  if (v->type != Json::Type::Number) throw std::runtime_error("not a float");
  return float(v->number);
}

// Three floats: a vector or a colour.
inline Vec3 read_vec(const Json* v) {
  if (v == nullptr || v->array.size() != 3) throw std::runtime_error("not three floats");
  return Vec3(read_float(&v->array[0]), read_float(&v->array[1]), read_float(&v->array[2]));
}

}  // namespace pt
