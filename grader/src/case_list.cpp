#include "grader/src/case_list.h"

#include <cctype>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

namespace grader {

const char* kind_name(CaseKind kind) {
  switch (kind) {
    case CaseKind::Image: return "image";
    case CaseKind::Rate: return "rate";
    case CaseKind::Speedup: return "speedup";
    case CaseKind::Probability: return "probability";
  }
  return "?";
}

bool parse_kind(const std::string& s, CaseKind* kind) {
  for (CaseKind k : {CaseKind::Image, CaseKind::Rate, CaseKind::Speedup, CaseKind::Probability}) {
    if (s == kind_name(k)) {
      *kind = k;
      return true;
    }
  }
  return false;
}

namespace {

bool parse_double(const std::string& s, double* out) {
  try {
    size_t used = 0;
    *out = std::stod(s, &used);
    return used == s.size();
  } catch (...) {
    return false;
  }
}

bool valid_name(const std::string& s) {
  if (s.empty() || s.size() > 64) return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-')) return false;
  return true;
}

}  // namespace

std::vector<Case> read_cases(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open the case list");
  std::vector<Case> cases;
  std::set<std::string> names;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    const size_t hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    std::istringstream fields(line);
    std::vector<std::string> f;
    for (std::string w; fields >> w;) f.push_back(w);
    if (f.empty()) continue;
    const auto fail = [&](const std::string& why) {
      throw std::runtime_error(path + ":" + std::to_string(number) + ": " + why);
    };
    if (f.size() < 6) fail("expected: name part kind points timeout scene [options...]");
    Case c;
    c.line = number;
    c.files_dir = std::filesystem::absolute(std::filesystem::path(path)).parent_path().string();
    c.name = f[0];
    if (!valid_name(c.name)) fail("case name '" + c.name + "' must be letters, digits, _ or -");
    if (!names.insert(c.name).second) fail("duplicate case name '" + c.name + "'");
    double part = 0;
    if (!parse_double(f[1], &part) || part < 1 || part > 9 || part != int(part)) fail("part must be 1..9");
    c.part = int(part);
    if (!parse_kind(f[2], &c.kind)) fail("unknown kind '" + f[2] + "' (image, rate, speedup, probability)");
    if (!parse_double(f[3], &c.points) || c.points < 0) fail("points must be a number >= 0");
    if (!parse_double(f[4], &c.timeout_seconds) || c.timeout_seconds <= 0) fail("timeout must be seconds > 0");
    c.scene = f[5];
    c.options.assign(f.begin() + 6, f.end());
    for (const std::string& o : c.options)
      if (o == "-f" || o == "--pfm" || o == "--stats-json" || o == "--seed" || o == "-t" || o == "--part" ||
          o == "--env-probability")
        fail("option " + o + " is set by the grader, not the case");
    cases.push_back(std::move(c));
  }
  if (cases.empty()) throw std::runtime_error(path + ": no cases");
  return cases;
}

std::string case_command(const Case& c) {
  std::string s = "--part " + std::to_string(c.part);
  for (const std::string& o : c.options) s += " " + o;
  return s + " " + c.scene;
}

std::string case_digest(const Case& c) {
  // FNV-1a over the definition; 64 bits is plenty to tell definitions apart.
  uint64_t h = 1469598103934665603ull;
  const std::string text = std::string(kind_name(c.kind)) + "|" + case_command(c);
  for (unsigned char ch : text) {
    h ^= ch;
    h *= 1099511628211ull;
  }
  char buf[20];
  std::snprintf(buf, sizeof buf, "%016llx", (unsigned long long)h);
  return buf;
}

}  // namespace grader
