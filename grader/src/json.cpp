#include "json.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace grader {

const Json* Json::get(const std::string& key) const {
  if (type != Type::Object) return nullptr;
  auto it = object.find(key);
  return it == object.end() ? nullptr : &it->second;
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

namespace {

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
        v.object[key] = value(depth + 1);
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
      v.number = std::strtod(begin, &end);
      if (end == begin) fail("unexpected character");
      i_ += size_t(end - begin);
      v.type = Json::Type::Number;
    }
    return v;
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
          if (i_ + 4 > s_.size()) fail("short \\u escape");
          const unsigned code = unsigned(std::stoul(s_.substr(i_, 4), nullptr, 16));
          i_ += 4;
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

Json parse_json(const std::string& text, const std::string& what) { return Parser(text, what).document(); }

Json read_json_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open");
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_json(ss.str(), path);
}

std::string json_number(double v) {
  if (!std::isfinite(v)) return "null";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

std::string flat_json(const Json& j) {
  std::string out = "{\n";
  size_t i = 0;
  for (const auto& [key, v] : j.object) {
    out += "  " + json_quote(key) + ": ";
    if (v.type == Json::Type::String) out += json_quote(v.string);
    else if (v.type == Json::Type::Bool) out += v.boolean ? "true" : "false";
    else if (v.type == Json::Type::Number) out += json_number(v.number);
    else out += "null";
    out += ++i < j.object.size() ? ",\n" : "\n";
  }
  return out + "}\n";
}

namespace {
Json& member(Json* object, const std::string& key) {
  object->type = Json::Type::Object;
  return object->object[key];
}
}  // namespace

void set_number(Json* object, const std::string& key, double v) {
  Json& m = member(object, key);
  m = Json();
  m.type = Json::Type::Number;
  m.number = v;
}

void set_string(Json* object, const std::string& key, const std::string& v) {
  Json& m = member(object, key);
  m = Json();
  m.type = Json::Type::String;
  m.string = v;
}

void set_bool(Json* object, const std::string& key, bool v) {
  Json& m = member(object, key);
  m = Json();
  m.type = Json::Type::Bool;
  m.boolean = v;
}

}  // namespace grader
