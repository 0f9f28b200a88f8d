// A strict JSON reader (RFC 8259) for checking the grader's reports: valid
// UTF-8 throughout, no raw control characters in strings, only the standard
// escapes, the standard number grammar, nothing after the value. Any
// departure throws std::runtime_error with the byte offset. (The grader's
// own reader is lenient on purpose, so it cannot judge its own output.)
#pragma once
#include <cstdlib>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace pt::test {

struct JsonValue {
  enum class Type { Null, Bool, Number, String, Array, Object } type = Type::Null;
  bool boolean = false;
  double number = 0;
  std::string string;
  std::vector<JsonValue> array;
  std::map<std::string, JsonValue> object;

  // The member `key` of an object; throws when absent.
  const JsonValue& at(const std::string& key) const {
    const auto it = object.find(key);
    if (type != Type::Object || it == object.end()) throw std::runtime_error("no member '" + key + "'");
    return it->second;
  }
  bool has(const std::string& key) const { return type == Type::Object && object.count(key) > 0; }
};

class StrictJson {
 public:
  static JsonValue parse(const std::string& text) {
    StrictJson p(text);
    p.check_utf8();
    JsonValue v = p.value(0);
    p.space();
    if (p.i_ != text.size()) p.fail("trailing characters");
    return v;
  }

 private:
  explicit StrictJson(const std::string& s) : s_(s) {}

  [[noreturn]] void fail(const std::string& why) const {
    throw std::runtime_error("invalid JSON: " + why + " at byte " + std::to_string(i_));
  }

  void check_utf8() {
    const auto* u = reinterpret_cast<const unsigned char*>(s_.data());
    for (size_t i = 0; i < s_.size();) {
      const unsigned c = u[i];
      size_t n = c < 0x80 ? 0 : (c >> 5) == 6 ? 1 : (c >> 4) == 14 ? 2 : (c >> 3) == 30 ? 3 : 99;
      if (n == 99 || c == 0xC0 || c == 0xC1 || c > 0xF4 || (n > 0 && i + n >= s_.size())) {
        i_ = i;
        fail("invalid UTF-8");
      }
      unsigned cp = n == 0 ? c : c & (0x3F >> n);
      for (size_t k = 1; k <= n; ++k) {
        if ((u[i + k] & 0xC0) != 0x80) {
          i_ = i;
          fail("invalid UTF-8");
        }
        cp = cp << 6 | (u[i + k] & 0x3F);
      }
      if ((n == 2 && cp < 0x800) || (n == 3 && (cp < 0x10000 || cp > 0x10FFFF)) || (cp >= 0xD800 && cp <= 0xDFFF)) {
        i_ = i;
        fail("invalid UTF-8 (overlong or surrogate)");
      }
      i += n + 1;
    }
  }

  void space() {
    while (i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\t' || s_[i_] == '\n' || s_[i_] == '\r')) ++i_;
  }
  char peek() const { return i_ < s_.size() ? s_[i_] : '\0'; }
  void expect(char c) {
    space();
    if (peek() != c) fail(std::string("expected '") + c + "'");
    ++i_;
  }
  bool literal(const char* w) {
    const std::string ws(w);
    if (s_.compare(i_, ws.size(), ws) != 0) return false;
    i_ += ws.size();
    return true;
  }
  static bool digit(char c) { return c >= '0' && c <= '9'; }

  JsonValue value(int depth) {
    if (depth > 100) fail("nested too deeply");
    space();
    JsonValue v;
    const char c = peek();
    if (c == '{') {
      ++i_;
      v.type = JsonValue::Type::Object;
      space();
      if (peek() == '}') {
        ++i_;
        return v;
      }
      for (;;) {
        space();
        if (peek() != '"') fail("expected a key");
        const std::string key = string();
        expect(':');
        v.object[key] = value(depth + 1);
        space();
        if (peek() == ',') {
          ++i_;
          continue;
        }
        expect('}');
        return v;
      }
    }
    if (c == '[') {
      ++i_;
      v.type = JsonValue::Type::Array;
      space();
      if (peek() == ']') {
        ++i_;
        return v;
      }
      for (;;) {
        v.array.push_back(value(depth + 1));
        space();
        if (peek() == ',') {
          ++i_;
          continue;
        }
        expect(']');
        return v;
      }
    }
    if (c == '"') {
      v.type = JsonValue::Type::String;
      v.string = string();
      return v;
    }
    if (literal("true")) {
      v.type = JsonValue::Type::Bool;
      v.boolean = true;
      return v;
    }
    if (literal("false")) {
      v.type = JsonValue::Type::Bool;
      return v;
    }
    if (literal("null")) return v;
    // -? (0 | [1-9][0-9]*) (. [0-9]+)? ([eE] [+-]? [0-9]+)?
    const size_t start = i_;
    if (peek() == '-') ++i_;
    if (peek() == '0') ++i_;
    else if (digit(peek())) while (digit(peek())) ++i_;
    else fail("unexpected character");
    if (peek() == '.') {
      ++i_;
      if (!digit(peek())) fail("a digit must follow '.'");
      while (digit(peek())) ++i_;
    }
    if (peek() == 'e' || peek() == 'E') {
      ++i_;
      if (peek() == '+' || peek() == '-') ++i_;
      if (!digit(peek())) fail("a digit must follow the exponent");
      while (digit(peek())) ++i_;
    }
    v.type = JsonValue::Type::Number;
    v.number = std::strtod(s_.substr(start, i_ - start).c_str(), nullptr);
    return v;
  }

  static int hex(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
  }

  void append_utf8(std::string* out, unsigned cp) {
    if (cp < 0x80) {
      *out += char(cp);
    } else if (cp < 0x800) {
      *out += char(0xC0 | (cp >> 6));
      *out += char(0x80 | (cp & 0x3F));
    } else if (cp < 0x10000) {
      *out += char(0xE0 | (cp >> 12));
      *out += char(0x80 | ((cp >> 6) & 0x3F));
      *out += char(0x80 | (cp & 0x3F));
    } else {
      *out += char(0xF0 | (cp >> 18));
      *out += char(0x80 | ((cp >> 12) & 0x3F));
      *out += char(0x80 | ((cp >> 6) & 0x3F));
      *out += char(0x80 | (cp & 0x3F));
    }
  }

  unsigned hex4() {
    unsigned v = 0;
    for (int k = 0; k < 4; ++k) {
      const int d = hex(peek());
      if (d < 0) fail("bad \\u escape");
      v = v << 4 | unsigned(d);
      ++i_;
    }
    return v;
  }

  std::string string() {
    ++i_;  // the opening quote
    std::string out;
    for (;;) {
      if (i_ >= s_.size()) fail("unterminated string");
      const char c = s_[i_];
      if (c == '"') {
        ++i_;
        return out;
      }
      if (static_cast<unsigned char>(c) < 0x20) fail("raw control character in a string");
      ++i_;
      if (c != '\\') {
        out += c;
        continue;
      }
      const char e = peek();
      ++i_;
      switch (e) {
        case '"': out += '"'; break;
        case '\\': out += '\\'; break;
        case '/': out += '/'; break;
        case 'b': out += '\b'; break;
        case 'f': out += '\f'; break;
        case 'n': out += '\n'; break;
        case 'r': out += '\r'; break;
        case 't': out += '\t'; break;
        case 'u': {
          unsigned cp = hex4();
          if (cp >= 0xDC00 && cp <= 0xDFFF) fail("lone low surrogate");
          if (cp >= 0xD800 && cp <= 0xDBFF) {
            if (!literal("\\u")) fail("lone high surrogate");
            const unsigned lo = hex4();
            if (lo < 0xDC00 || lo > 0xDFFF) fail("bad surrogate pair");
            cp = 0x10000 + ((cp - 0xD800) << 10) + (lo - 0xDC00);
          }
          append_utf8(&out, cp);
          break;
        }
        default: fail("unknown escape");
      }
    }
  }

  const std::string& s_;
  size_t i_ = 0;
};

}  // namespace pt::test
