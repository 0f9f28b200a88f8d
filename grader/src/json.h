// A small JSON value: enough to read the renderer's --stats-json, the
// references' metadata and the per-case results that `grader merge` joins.
#pragma once
#include <map>
#include <memory>
#include <string>
#include <vector>

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

// "text" with quotes and escapes.
std::string json_quote(const std::string& s);
// A number as JSON: finite values printed with up to 9 significant digits,
// NaN and infinities as null (JSON has no spelling for them).
std::string json_number(double v);

}  // namespace grader
