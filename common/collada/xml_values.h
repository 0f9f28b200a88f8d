// Values written as XML text: whitespace-separated number lists, exact
// counts of finite numbers, colours and count attributes. Each reader fails
// with a message naming the element when the text is not what it needs.
#pragma once
#include <charconv>
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>
#include <system_error>
#include <type_traits>
#include <vector>

#include "common/collada/messages.h"

namespace pt::collada {

inline bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

std::string_view trim(std::string_view s);

// The character data of `e`. Usually a view of tinyxml2's own string; text
// split by comments or CDATA sections is joined into `buf`.
std::string_view element_text(const XMLElement* e, std::string& buf);

// Parses whitespace-separated numbers into `out`. On a token that is not a
// number (or out of the type's range) returns false with the token in `bad`.
template <typename T>
bool parse_list(std::string_view s, std::vector<T>& out, std::string_view* bad) {
  const char* p = s.data();
  const char* end = p + s.size();
  while (true) {
    while (p < end && is_space(*p)) ++p;
    if (p == end) return true;
    const char* tok = p;
    while (p < end && !is_space(*p)) ++p;
    const char* first = tok;
    if (*first == '+' && first + 1 < p && first[1] != '-' && first[1] != '+') ++first;  // xs:double allows '+'
    T v{};
    auto r = std::from_chars(first, p, v);
    if constexpr (std::is_floating_point_v<T>) {
      // Out of double's range: underflow reads as zero, overflow as infinity
      // (which the callers reject where a finite number is needed).
      if (r.ec == std::errc::result_out_of_range && r.ptr == p) {
        const std::string_view t(first, static_cast<size_t>(p - first));
        const bool negative = t.front() == '-';
        const bool tiny = t.find("e-") != t.npos || t.find("E-") != t.npos;
        v = tiny ? (negative ? -0.0 : 0.0) : (negative ? -HUGE_VAL : HUGE_VAL);
        r.ec = std::errc();
      }
    }
    if (r.ec != std::errc() || r.ptr != p) {
      *bad = std::string_view(tok, static_cast<size_t>(p - tok));
      return false;
    }
    out.push_back(v);
  }
}

// Upper bound on how many numbers a text can hold (each needs a character
// and a separator); caps reservations made from count attributes.
inline size_t max_numbers(std::string_view s) { return s.size() / 2 + 1; }

// The numbers of `e`'s text, any count, finite or not.
std::vector<double> numbers(const Messages& msg, const XMLElement* e);

// Exactly `n` finite numbers; `what` says what they are for the message.
std::vector<double> numbers(const Messages& msg, const XMLElement* e, size_t n, const char* what);

// One finite number.
double scalar(const Messages& msg, const XMLElement* e, const char* what);

// A colour: three finite, non-negative numbers within float's range (a
// fourth, alpha, is allowed and ignored where COLLADA writes RGBA).
Vec3d rgb(const Messages& msg, const XMLElement* e, bool allow_alpha);

// A non-negative integer attribute; false when absent.
bool count_attribute(const Messages& msg, const XMLElement* e, const char* name, uint64_t* out);

}  // namespace pt::collada
