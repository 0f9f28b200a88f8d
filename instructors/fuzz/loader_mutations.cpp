// The mutations of fuzz_loaders (see loader_mutations.h).
#include "instructors/fuzz/loader_mutations.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

namespace fuzz {

namespace {

// ---- Mutations ---------------------------------------------------------------

const std::vector<std::string> kNumbers = {
    "0", "-0", "1", "-1", "2", "nan", "NaN", "-nan", "inf", "-inf", "INF", "1e308", "1e309", "-1e309", "1e-320",
    "2147483647", "2147483648", "-2147483649", "4294967296", "18446744073709551616", "99999999999999999999999",
    "3.4e38", "3.5e38", "1e39", "65536", "16777217", "0.5", "1e-7", ".", "-", "+", "e", "0x10", "1e", "--1", ""};

const std::vector<std::string> kSceneTokens = {
    "<node>", "</node>", "<node id=\"n\">", "<instance_node url=\"#n\"/>", "<instance_node url=\"#Scene\"/>",
    "<matrix>1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1</matrix>", "<matrix>1 0 0</matrix>", "<matrix>", "</matrix>", "<p>",
    "</p>", "<vcount>", "</vcount>", "<![CDATA[", "]]>", "<!--", "-->", "&amp;", "&#0;", "&#xFFFF;", "&lt;", "\"",
    "'", "=", "/>", "<", ">", "#", " count=\"", " offset=\"", " stride=\"", " url=\"#", " source=\"#", " id=\"",
    " material=\"", " symbol=\"", " target=\"#", "<instance_geometry url=\"#\"/>",
    "<extra><technique profile=\"CGL\"><sphere><radius>1</radius></sphere></technique></extra>",
    "<up_axis>X_UP</up_axis>", "<up_axis>Z_UP</up_axis>", "<lookat>0 0 5 0 0 0 0 1 0</lookat>",
    "<rotate>0 0 1 45</rotate>", "<scale>0 0 0</scale>", "<translate>1e308 0 0</translate>", "<skew>1</skew>",
    "<ph><p>0 1 2</p><h>0 1 2</h></ph>", "<input semantic=\"VERTEX\" source=\"#\" offset=\"4096\"/>",
    "<input semantic=\"NORMAL\" source=\"#\" offset=\"1\"/>", "<triangles count=\"1\">", "</triangles>",
    "<polygons>", "<lines>", "<instance_controller/>", "<instance_light url=\"#\"/>",
    "<instance_camera url=\"#\"/>", "<spot><color>1 1 1</color></spot>", "<texture texture=\"t\"/>", "\n", " ",
    "\t", "\xef\xbb\xbf", "\xff", std::string(1, '\0')};

const std::vector<std::string> kCameraTokens = {"\n", " ", "\t", "\r", "nan", "inf", "-inf", "1e999", "0", "-1",
                                                "180", "0x1p3", "#", "1 0 0 0 1 0 0 0 1", "0 0 0",
                                                std::string(1, '\0')};

const std::vector<int32_t> kInts = {0, 1, -1, 2, 3, 7, 8, 16, 31, 32, 255, 256, 4096, 32767, 32768, 65535, 65536,
                                    0x7fffffff, int32_t(0x80000000), int32_t(0xffff0000), 100000, -100000};

size_t random_pos(Random& rng, const std::string& s) { return rng.below(s.size() + 1); }

// A span [pos, pos + len) of `s` of up to `max_len` bytes.
std::pair<size_t, size_t> random_span(Random& rng, const std::string& s, size_t max_len) {
  if (s.empty()) return {0, 0};
  const size_t pos = rng.below(s.size());
  const size_t len = 1 + rng.below(std::min(max_len, s.size() - pos));
  return {pos, len};
}

// Replaces the number nearest after a random position with another.
void replace_number(Random& rng, std::string& s) {
  if (s.empty()) return;
  size_t p = s.find_first_of("0123456789", rng.below(s.size()));
  if (p == std::string::npos) p = s.find_first_of("0123456789");
  if (p == std::string::npos) return;
  size_t b = p, e = p;
  auto numeric = [](char c) { return std::isdigit(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '+' || c == 'e' || c == 'E'; };
  while (b > 0 && numeric(s[b - 1])) --b;
  while (e < s.size() && numeric(s[e])) ++e;
  s.replace(b, e - b, rng.pick(kNumbers));
}

// The extent [open, end) of a whole element starting at or after a random
// position; false when none is found.
bool find_element(Random& rng, const std::string& s, size_t* open_at, size_t* end_at, std::string* name_out) {
  for (int attempt = 0; attempt < 8 && !s.empty(); ++attempt) {
    const size_t open = s.find('<', rng.below(s.size()));
    if (open == std::string::npos || open + 1 >= s.size() || !std::isalpha(static_cast<unsigned char>(s[open + 1])))
      continue;
    size_t name_end = open + 1;
    while (name_end < s.size() && (std::isalnum(static_cast<unsigned char>(s[name_end])) || s[name_end] == '_'))
      ++name_end;
    const std::string name = s.substr(open + 1, name_end - open - 1);
    const size_t gt = s.find('>', name_end);
    if (gt == std::string::npos) continue;
    size_t end;
    if (s[gt - 1] == '/') {
      end = gt + 1;
    } else {
      const size_t close = s.find("</" + name + ">", gt);
      if (close == std::string::npos) continue;
      end = close + name.size() + 3;
    }
    *open_at = open;
    *end_at = end;
    *name_out = name;
    return true;
  }
  return false;
}

const std::vector<std::string> kElementNames = {
    "node", "instance_node", "instance_geometry", "instance_geometery", "instance_light", "instance_camera",
    "matrix", "translate", "rotate", "scale", "lookat", "skew", "polylist", "triangles", "polygons", "lines",
    "p", "vcount", "input", "source", "vertices", "mesh", "extra", "technique", "technique_common", "color",
    "radius", "sphere", "area", "point", "spot", "directional", "ambient", "emission", "glass", "mirror",
    "microfacet", "refraction", "xfov", "yfov", "aspect_ratio", "znear", "zfar", "asset", "up_axis", "unknown"};

// Removes a whole element, or renames one (start and end tag alike).
void delete_or_rename_element(Random& rng, std::string& s) {
  size_t open = 0, end = 0;
  std::string name;
  if (!find_element(rng, s, &open, &end, &name)) return;
  if (rng.chance(0.4)) {
    s.erase(open, end - open);
    return;
  }
  const std::string to = rng.pick(kElementNames);
  const size_t close = end - name.size() - 3;
  if (s.compare(close, 2, "</") == 0) s.replace(close + 2, name.size(), to);
  s.replace(open + 1, name.size(), to);
}

// Copies a whole element (from a random '<name' to its matching '</name>')
// and inserts the copy right after it.
void duplicate_element(Random& rng, std::string& s) {
  size_t open = 0, end = 0;
  std::string name;
  if (find_element(rng, s, &open, &end, &name) && end - open <= 200000) s.insert(end, s.substr(open, end - open));
}

// Inserts a dictionary token just after a tag, where markup may go.
void insert_after_tag(Random& rng, std::string& s) {
  size_t at = s.find('>', rng.below(s.size() + 1));
  at = at == std::string::npos ? s.size() : at + 1;
  s.insert(at, rng.pick(kSceneTokens));
}

// Points a random url/source/target reference at another id of the file.
void rewire_reference(Random& rng, std::string& s) {
  std::vector<std::string> ids;
  for (size_t p = s.find(" id=\""); p != std::string::npos && ids.size() < 2000; p = s.find(" id=\"", p + 1)) {
    const size_t e = s.find('"', p + 5);
    if (e == std::string::npos) break;
    ids.push_back(s.substr(p + 5, e - p - 5));
  }
  if (ids.empty()) return;
  size_t p = s.find("=\"#", rng.below(s.size()));
  if (p == std::string::npos) p = s.find("=\"#");
  if (p == std::string::npos) return;
  const size_t e = s.find('"', p + 3);
  if (e == std::string::npos) return;
  s.replace(p + 3, e - p - 3, rng.pick(ids));
}

}  // namespace

void mutate(Random& rng, std::string& s, Kind kind, const std::vector<Seed>& pool) {
  const int ops = 1 + int(rng.below(3)) + (rng.chance(0.15) ? int(rng.below(8)) : 0);
  for (int i = 0; i < ops; ++i) {
    // Scenes: mostly changes that keep the XML well formed, so that the
    // loader's own checks are reached (byte-level ones mostly stop at the
    // XML parser).
    if (kind == Kind::Scene && rng.chance(0.7)) {
      switch (rng.below(5)) {
        case 0: replace_number(rng, s); break;
        case 1: duplicate_element(rng, s); break;
        case 2: delete_or_rename_element(rng, s); break;
        case 3: rewire_reference(rng, s); break;
        default: insert_after_tag(rng, s); break;
      }
      continue;
    }
    const int op = int(rng.below(kind == Kind::Exr ? 9 : 11));
    switch (op) {
      case 0:  // flip a bit
        if (!s.empty()) s[rng.below(s.size())] ^= char(1u << rng.below(8));
        break;
      case 1: {  // an interesting byte
        static const char bytes[] = {'\0', '\xff', '\x7f', '\x80', '<', '>', '"', ' ', '-', '0', '9', 'e', '.', '/', '#'};
        if (!s.empty()) s[rng.below(s.size())] = bytes[rng.below(sizeof bytes)];
        break;
      }
      case 2: {  // delete a span
        const auto [pos, len] = random_span(rng, s, rng.chance(0.1) ? 4096 : 64);
        s.erase(pos, len);
        break;
      }
      case 3: {  // duplicate a span
        const auto [pos, len] = random_span(rng, s, 256);
        const std::string copy = s.substr(pos, len);
        s.insert(random_pos(rng, s), copy);
        break;
      }
      case 4: {  // splice from another seed of the same kind
        std::vector<const Seed*> same;
        for (const Seed& seed : pool)
          if (seed.kind == kind) same.push_back(&seed);
        const std::string& other = same[rng.below(same.size())]->bytes;
        const auto [pos, len] = random_span(rng, other, 512);
        const std::string piece = other.substr(pos, len);
        const size_t at = random_pos(rng, s);
        if (rng.chance(0.5))
          s.insert(at, piece);
        else
          s.replace(at, std::min(piece.size(), s.size() - at), piece);
        break;
      }
      case 5:  // truncate
        if (rng.chance(0.3)) s.resize(rng.below(s.size() + 1));
        break;
      case 6:
      case 7:
      case 8:
        if (kind == Kind::Exr) {  // a header integer: mostly within the first 400 bytes
          if (s.size() < 4) break;
          const size_t limit = rng.chance(0.8) ? std::min<size_t>(s.size() - 3, 400) : s.size() - 3;
          const size_t at = rng.below(limit);
          int32_t v = rng.chance(0.8) ? kInts[rng.below(kInts.size())] : int32_t(rng.next());
          if (rng.chance(0.3)) v = int32_t(uint32_t(v) + uint32_t(rng.below(5)) - 2u);
          std::memcpy(&s[at], &v, 4);
        } else if (op == 6) {
          replace_number(rng, s);
        } else {  // a dictionary token
          const auto& dict = kind == Kind::Scene ? kSceneTokens : kCameraTokens;
          s.insert(random_pos(rng, s), rng.pick(dict));
        }
        break;
      case 9:
        if (kind == Kind::Scene) duplicate_element(rng, s); else replace_number(rng, s);
        break;
      case 10:
        if (kind == Kind::Scene) rewire_reference(rng, s); else replace_number(rng, s);
        break;
    }
  }
}

}  // namespace fuzz
