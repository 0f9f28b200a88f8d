// A small JSON value: enough to read the renderer's --stats-json, the
// references' metadata and the per-case results that `grader merge` joins.
#pragma once
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "json_text.h"

namespace grader {

struct Json {
  enum class Type { Null, Bool, Number, String, Array, Object };
  Type type = Type::Null;
  bool boolean = false;
  double number = 0.0;
  std::string string;
  std::vector<Json> array;
  std::map<std::string, Json> object;

  // Lookups that never throw: a missing key or a wrong type gives `fallback`.
  double num(const std::string& key, double fallback = 0.0) const;
  std::string str(const std::string& key, const std::string& fallback = "") const;
  bool flag(const std::string& key, bool fallback = false) const;
  const Json* get(const std::string& key) const;
};

// Throws std::runtime_error("<what>: <reason> at offset N") on malformed text.
Json parse_json(const std::string& text, const std::string& what);
Json read_json_file(const std::string& path);

using pt::json_quote;  // "text" with quotes and escapes
// A number as JSON: finite values printed with up to 9 significant digits,
// NaN and infinities as null (JSON has no spelling for them).
std::string json_number(double v);
// A flat object (numbers, strings, booleans; anything else as null), one
// member per line, keys in order: how meta.json files are written.
std::string flat_json(const Json& j);
// Builders for such objects.
void set_number(Json* object, const std::string& key, double v);
void set_string(Json* object, const std::string& key, const std::string& v);
void set_bool(Json* object, const std::string& key, bool v);

}  // namespace grader
