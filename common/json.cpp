#include "common/json.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace pt {

const Json* Json::get(const std::string& key) const {
  if (type != Type::Object) return nullptr;
  // From the back: the last of a repeated key wins, as in any reader that
  // fills a map.
  for (auto it = members.rbegin(); it != members.rend(); ++it)
    if (it->first == key) return &it->second;
  return nullptr;
}

double Json::num(const std::string& key, double fallback) const {
  const Json* v = get(key);
  return v && v->type == Type::Number ? v->number : fallback;
}

std::string Json::str(const std::string& key, const std::string& fallback) const {
  const Json* v = get(key);
  return v && v->type == Type::String ? v->string : fallback;
}

bool Json::flag(const std::string& key, bool fallback) const {
  const Json* v = get(key);
  return v && v->type == Type::Bool ? v->boolean : fallback;
}

Json& Json::set(const std::string& key, Json value) {
  if (type != Type::Object) *this = json_object(one_line);
  for (auto it = members.rbegin(); it != members.rend(); ++it)
    if (it->first == key) {
      it->second = std::move(value);
      return *this;
    }
  members.emplace_back(key, std::move(value));
  return *this;
}

Json json_object(bool one_line) {
  Json j;
  j.type = Json::Type::Object;
  j.one_line = one_line;
  return j;
}

Json json_array(std::vector<Json> items, bool one_line) {
  Json j;
  j.type = Json::Type::Array;
  j.array = std::move(items);
  j.one_line = one_line;
  return j;
}

Json json_text(const std::string& s) {
  Json j;
  j.type = Json::Type::String;
  j.string = s;
  return j;
}

Json json_bool(bool b) {
  Json j;
  j.type = Json::Type::Bool;
  j.boolean = b;
  return j;
}

namespace {

Json number_spelled(double v, const std::string& spelling) {
  Json j;
  j.type = Json::Type::Number;
  j.number = v;
  j.string = spelling;
  return j;
}

}  // namespace

Json json_real(double v, const char* format) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return number_spelled(v, buf);
}

Json json_int(long long v) { return number_spelled(double(v), std::to_string(v)); }

Json json_count(uint64_t v) { return number_spelled(double(v), std::to_string(v)); }

std::string json_quote(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (c == '\n') {
      out += "\\n";
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", unsigned(static_cast<unsigned char>(c)));
      out += buf;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string json_number(double v) {
  if (!std::isfinite(v)) return "null";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

namespace {

void write_value(const Json& v, const std::string& indent, std::string* out) {
  switch (v.type) {
    case Json::Type::Null: *out += "null"; return;
    case Json::Type::Bool: *out += v.boolean ? "true" : "false"; return;
    case Json::Type::Number:
      // A number made by json_real, json_int or json_count keeps its
      // spelling; one read from text gets 9 significant digits; one that is
      // not finite has no spelling in JSON.
      *out += !std::isfinite(v.number) ? "null" : v.string.empty() ? json_number(v.number) : v.string;
      return;
    case Json::Type::String: *out += json_quote(v.string); return;
    case Json::Type::Array:
    case Json::Type::Object: break;
  }
  const bool object = v.type == Json::Type::Object;
  const size_t n = object ? v.members.size() : v.array.size();
  const std::string inner = indent + "  ";
  *out += object ? '{' : '[';
  if (!v.one_line) *out += '\n';
  for (size_t i = 0; i < n; ++i) {
    if (!v.one_line) *out += inner;
    if (object) *out += json_quote(v.members[i].first) + ": ";
    write_value(object ? v.members[i].second : v.array[i], inner, out);
    if (i + 1 < n) *out += v.one_line ? ", " : ",\n";
  }
  if (!v.one_line) *out += (n > 0 ? "\n" : "") + indent;
  *out += object ? '}' : ']';
}

class Parser {
 public:
  Parser(const std::string& text, const std::string& what) : s_(text), what_(what) {}

  Json document() {
    Json v = value(0);
    skip_space();
    if (i_ != s_.size()) fail("trailing characters");
    return v;
  }

 private:
  [[noreturn]] void fail(const std::string& why) const {
    throw std::runtime_error(what_ + ": malformed JSON (" + why + ") at offset " + std::to_string(i_));
  }
  void skip_space() {
    while (i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\n' || s_[i_] == '\t' || s_[i_] == '\r')) ++i_;
  }
  bool eat(char c) {
    skip_space();
    if (i_ < s_.size() && s_[i_] == c) {
      ++i_;
      return true;
    }
    return false;
  }
  void expect(char c) {
    if (!eat(c)) fail(std::string("expected '") + c + "'");
  }
  bool word(const char* w) {
    const std::string ws(w);
    if (s_.compare(i_, ws.size(), ws) == 0) {
      i_ += ws.size();
      return true;
    }
    return false;
  }

  Json value(int depth) {
    if (depth > 64) fail("nested too deeply");
    skip_space();
    if (i_ >= s_.size()) fail("unexpected end");
    Json v;
    const char c = s_[i_];
    if (c == '{') {
      ++i_;
      v.type = Json::Type::Object;
      if (eat('}')) return v;
      do {
        skip_space();
        if (i_ >= s_.size() || s_[i_] != '"') fail("expected a key");
        std::string key = string();
        expect(':');
        // Appended, not set: a file of many keys must not take quadratic
        // time; lookups take the last of a repeated key.
        v.members.emplace_back(std::move(key), value(depth + 1));
      } while (eat(','));
      expect('}');
    } else if (c == '[') {
      ++i_;
      v.type = Json::Type::Array;
      if (eat(']')) return v;
      do v.array.push_back(value(depth + 1));
      while (eat(','));
      expect(']');
    } else if (c == '"') {
      v.type = Json::Type::String;
      v.string = string();
    } else if (word("true")) {
      v.type = Json::Type::Bool;
      v.boolean = true;
    } else if (word("false")) {
      v.type = Json::Type::Bool;
    } else if (word("null")) {
      v.type = Json::Type::Null;
    } else {
      const char* begin = s_.c_str() + i_;
      char* end = nullptr;
      const double number = std::strtod(begin, &end);
      if (end == begin) fail("unexpected character");
      i_ += size_t(end - begin);
      v.type = Json::Type::Number;
      v.number = number;  // no spelling kept: written again with 9 digits
    }
    return v;
  }

  unsigned hex4() {
    if (i_ + 4 > s_.size()) fail("short \\u escape");
    unsigned code = 0;
    for (int k = 0; k < 4; ++k) {
      const char h = s_[i_ + size_t(k)];
      const int d = h >= '0' && h <= '9' ? h - '0' : h >= 'a' && h <= 'f' ? h - 'a' + 10 : h >= 'A' && h <= 'F' ? h - 'A' + 10 : -1;
      if (d < 0) fail("bad \\u escape");
      code = code << 4 | unsigned(d);
    }
    i_ += 4;
    return code;
  }

  std::string string() {
    ++i_;  // opening quote
    std::string out;
    while (i_ < s_.size() && s_[i_] != '"') {
      char c = s_[i_++];
      if (c != '\\') {
        out += c;
        continue;
      }
      if (i_ >= s_.size()) break;
      c = s_[i_++];
      switch (c) {
        case 'n': out += '\n'; break;
        case 't': out += '\t'; break;
        case 'r': out += '\r'; break;
        case 'b': out += '\b'; break;
        case 'f': out += '\f'; break;
        case 'u': {
          const unsigned code = hex4();
          // Enough for what we write (control characters) and the BMP.
          if (code < 0x80) {
            out += char(code);
          } else if (code < 0x800) {
            out += char(0xC0 | (code >> 6));
            out += char(0x80 | (code & 0x3F));
          } else {
            out += char(0xE0 | (code >> 12));
            out += char(0x80 | ((code >> 6) & 0x3F));
            out += char(0x80 | (code & 0x3F));
          }
          break;
        }
        default: out += c;
      }
    }
    if (i_ >= s_.size()) fail("unterminated string");
    ++i_;  // closing quote
    return out;
  }

  const std::string& s_;
  const std::string& what_;
  size_t i_ = 0;
};

}  // namespace

std::string write_json(const Json& value) {
  std::string out;
  write_value(value, "", &out);
  return out + "\n";
}

Json parse_json(const std::string& text, const std::string& what) { return Parser(text, what).document(); }

Json read_json_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open");
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_json(ss.str(), path);
}

}  // namespace pt
