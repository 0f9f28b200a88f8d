// JSON for the files the renderer and the grader write and read (the
// renderer's --stats-json, the references' meta.json, the grader's per-case
// result.json and Gradescope's results.json): one value type, one writer,
// one reader.
//
// The writer lays a value out one member per line, two spaces per level,
// except objects and arrays marked `one_line`; an object keeps its members
// in the order they were set, and a number made here keeps the spelling it
// was made with (a count exactly, a time to a fixed number of decimals). The reader
// is lenient (it reads what any of the project's writers and a student's
// renderer may write) and never throws anything but std::runtime_error.
#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace pt {

struct Json {
  enum class Type { Null, Bool, Number, String, Array, Object };
  Type type = Type::Null;
  bool boolean = false;
  double number = 0.0;
  std::string string;    // a String's text; a Number's spelling (empty: 9 digits)
  std::vector<Json> array;
  std::vector<std::pair<std::string, Json>> members;  // an Object's, in order
  bool one_line = false;  // an Array or Object written on one line

  // Lookups that never throw: a missing key or a wrong type gives `fallback`.
  // A key given twice means its last value.
  const Json* get(const std::string& key) const;
  double num(const std::string& key, double fallback = 0.0) const;
  std::string str(const std::string& key, const std::string& fallback = "") const;
  bool flag(const std::string& key, bool fallback = false) const;

  // Sets member `key` (replacing its value, or appending it); makes this an
  // object. Returns *this, so that members can be chained.
  Json& set(const std::string& key, Json value);
};

// Values. A number that is NaN or infinite is written as null (JSON has no
// spelling for it).
Json json_object(bool one_line = false);
Json json_array(std::vector<Json> items, bool one_line = false);
Json json_text(const std::string& s);
Json json_bool(bool b);
// A double with up to 9 significant digits, or with `format` (a printf
// format of one double, e.g. "%.6f").
Json json_real(double v, const char* format = "%.9g");
Json json_int(long long v);
Json json_count(uint64_t v);  // exactly, beyond double's 2^53

// The text of a value as the writer lays it out, ending in a newline.
std::string write_json(const Json& value);

// Throws std::runtime_error("<what>: malformed JSON (<reason>) at offset N").
Json parse_json(const std::string& text, const std::string& what);
// Throws std::runtime_error naming the file.
Json read_json_file(const std::string& path);

// "text" with quotes, backslashes, newlines and other control characters
// escaped.
std::string json_quote(const std::string& s);
// A number as JSON: up to 9 significant digits; NaN and infinities as null.
std::string json_number(double v);

}  // namespace pt
