// A seeded mutation fuzzer for the readers of untrusted files: the COLLADA
// loader (load_collada), the camera settings file (-c, Camera::load_settings)
// and the OpenEXR environment map (-e, load_environment_map). It is built
// with AddressSanitizer and UndefinedBehaviorSanitizer (see CMakeLists.txt),
// so a memory error or undefined behaviour aborts the run with a report.
//
// Each iteration takes a seed file, applies a few random mutations (bit
// flips, deletions, duplications, splices, tokens and numbers from a
// dictionary, duplicated XML elements, rewired references, header integers),
// writes the result to a file and reads it. Beyond the sanitizers it checks
// the readers' contract: an input is either read, giving a scene (or camera,
// or map) whose numbers are finite and consistent, or refused with the
// documented exception whose message is one line starting with the file's
// path; warnings are one line starting with the path. A scene that loads
// also gets a BVH (part 2's build, sanitized too) and a few rays through it.
// The same seed gives
// the same inputs, so a finding can be replayed.
//
//   fuzz_loaders [--seed N] [--iterations N] [--seconds S] [--max-seed-bytes N]
//                [--timeout S] [--work DIR] [--skip-without PATH] INPUT...
//
// INPUTs are files or folders (whose .dae, .exr and .txt files are taken);
// one that does not exist is an error, so that a run's seed set never
// changes silently. --skip-without PATH makes the run exit with 77 (ctest's
// "skipped") when PATH is absent: the run over the course's scenes, which
// may not be beside the checkout, is its own test. .dae files are scenes,
// .exr files environment maps, anything else a camera settings file. Seeds
// larger than --max-seed-bytes (default 400000) are read once unmutated but
// not mutated. Exit status 0 when nothing was found, 1 on a finding, 2 on
// bad arguments, 77 when skipped.
#include <sanitizer/common_interface_defs.h>
#include <signal.h>
#include <unistd.h>

#include <ImfRgbaFile.h>

#include <array>
#include <ImfTiledRgbaFile.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <typeinfo>
#include <vector>

#include "stages/part2_bvh/bvh.h"
#include "common/camera.h"
#include "common/collada.h"
#include "common/environment.h"
#include "common/scene.h"

namespace fs = std::filesystem;

namespace {

// ---- Random numbers (SplitMix64: the same sequence on every platform) ----

struct Random {
  uint64_t state;
  explicit Random(uint64_t seed) : state(seed) {}
  uint64_t next() {
    uint64_t z = (state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  size_t below(size_t n) { return n == 0 ? 0 : size_t(next() % n); }
  bool chance(double p) { return double(next() >> 11) * 0x1.0p-53 < p; }
  double uniform() { return double(next() >> 11) * 0x1.0p-53; }
  template <typename T>
  const T& pick(const std::vector<T>& v) { return v[below(v.size())]; }
};

enum class Kind { Scene, Camera, Exr };
const char* kind_name(Kind k) { return k == Kind::Scene ? "dae" : k == Kind::Camera ? "camera" : "exr"; }
const char* kind_ext(Kind k) { return k == Kind::Scene ? ".dae" : k == Kind::Camera ? ".txt" : ".exr"; }

struct Seed {
  std::string name;
  Kind kind;
  std::string bytes;
};

// ---- What is being read, for a report if the process dies ----------------

std::string g_current_input;  // the file being read
std::string g_current_label;  // "iteration 12 (dae, from CBempty.dae)"
uint64_t g_seed = 1;

void save_current_input(const char* why) {
  if (g_current_input.empty()) return;
  const std::string keep = "fuzz-finding" + fs::path(g_current_input).extension().string();
  std::error_code ec;
  fs::copy_file(g_current_input, keep, fs::copy_options::overwrite_existing, ec);
  std::fprintf(stderr, "fuzz_loaders: %s while reading %s, seed %llu; the input is saved as %s\n", why,
               g_current_label.c_str(), (unsigned long long)g_seed, ec ? g_current_input.c_str() : keep.c_str());
}

void on_sanitizer_death() { save_current_input("sanitizer report"); }
void on_terminate() {
  save_current_input("std::terminate");
  std::abort();
}
void on_alarm(int) {
  save_current_input("time limit exceeded (a hang)");
  std::_Exit(1);
}

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

// ---- Reading and checking ------------------------------------------------------

struct Outcome {
  std::string key;      // the class of result, for counting distinct outcomes
  std::string finding;  // non-empty: the reader broke its contract
};

// A message reduced to its shape: numbers, quoted text and ids removed.
std::string shape(const std::string& path, std::string m) {
  if (m.rfind(path + ": ", 0) == 0) m = m.substr(path.size() + 2);
  std::string out;
  for (size_t i = 0; i < m.size() && out.size() < 90; ++i) {
    const char c = m[i];
    if (std::isdigit(static_cast<unsigned char>(c))) {
      if (out.empty() || out.back() != '#') out += '#';
    } else if (c == '\'' || c == '"') {
      const size_t e = m.find(c, i + 1);
      if (e == std::string::npos) break;
      out += "..";
      i = e;
    } else {
      out += c;
    }
  }
  return out;
}

bool one_line_from(const std::string& m, const std::string& path) {
  return m.rfind(path + ": ", 0) == 0 && m.find('\n') == std::string::npos && m.find('\r') == std::string::npos;
}

bool unit(const pt::Vec3& n) { return pt::is_finite(n) && std::fabs(pt::norm(n) - 1.0f) < 1e-3f; }

std::string check_scene(const pt::Scene& s) {
  if (s.num_primitives() == 0) return "a scene without primitives was accepted";
  if (s.num_primitives() > pt::kMaxScenePrimitives) return "more primitives than the limit";
  for (const pt::Triangle& t : s.triangles) {
    if (!pt::is_finite(t.p1) || !pt::is_finite(t.p2) || !pt::is_finite(t.p3)) return "a triangle is not finite";
    if (!unit(t.n1) || !unit(t.n2) || !unit(t.n3)) return "a triangle normal is not unit length";
    if (t.material < 0 || size_t(t.material) >= s.materials.size()) return "a triangle's material is out of range";
  }
  for (const pt::Sphere& sp : s.spheres) {
    if (!pt::is_finite(sp.center) || !(sp.radius > 0) || !std::isfinite(sp.radius)) return "a sphere is degenerate";
    if (sp.material < 0 || size_t(sp.material) >= s.materials.size()) return "a sphere's material is out of range";
  }
  for (const pt::Light& l : s.lights)
    if (!pt::is_finite(l.radiance) || !pt::is_finite(l.position) || !pt::is_finite(l.direction))
      return "a light is not finite";
  const pt::Camera& c = s.camera;
  if (!pt::is_finite(c.position) || !pt::is_finite(c.axis_x) || !pt::is_finite(c.axis_y) || !pt::is_finite(c.axis_z))
    return "the camera is not finite";
  if (!(c.hfov_deg > 0 && c.hfov_deg < 180 && c.vfov_deg > 0 && c.vfov_deg < 180)) return "the camera's FOV is out of range";
  if (!(c.near_clip >= 0 && c.far_clip > c.near_clip)) return "the camera's clip range is wrong";
  return "";
}

// The BVH over a loaded scene (part 2's build, under the sanitizers: its
// binning turns centroid coordinates into bin numbers, which a scene with
// coordinates near 1e38 or a zero extent must not make undefined), and a
// few rays through it: every hit inside the ray's interval, with a unit
// normal. Scenes over kMaxBvhPrimitives are skipped to keep runs short.
constexpr size_t kMaxBvhPrimitives = 20000;

std::string check_bvh(const pt::Scene& s, Random& rng) {
  if (s.num_primitives() > kMaxBvhPrimitives) return "";
  const pt::BVH bvh(s);
  const pt::BBox b = s.bounds();
  for (int i = 0; i < 16; ++i) {
    const auto lerp = [&](float lo, float hi) { return float(lo + (double(hi) - lo) * rng.uniform()); };
    const pt::Vec3 o(lerp(b.lo.x, b.hi.x), lerp(b.lo.y, b.hi.y), lerp(b.lo.z, b.hi.z));
    pt::Vec3 d(float(rng.uniform() * 2 - 1), float(rng.uniform() * 2 - 1), float(rng.uniform() * 2 - 1));
    if (pt::norm(d) < 1e-3f) continue;
    d = pt::normalize(d);
    pt::Ray r(o, d, 1e-4f, std::numeric_limits<float>::infinity());
    pt::Hit hit;
    if (bvh.intersect(r, &hit)) {
      if (!(hit.t >= 1e-4f && hit.t == r.max_t)) return "a BVH hit lies outside the ray's interval";
      if (!unit(hit.n)) return "a BVH hit's normal is not unit length";
    }
    bvh.occluded(pt::Ray(o, d, 1e-4f, 1.0f));
  }
  return "";
}

std::string check_camera(const pt::Camera& c, Random& rng) {
  if (!pt::is_finite(c.position) || !std::isfinite(c.focal_distance) || !(c.focal_distance > 0) ||
      !(c.lens_radius >= 0) || !std::isfinite(c.lens_radius))
    return "the camera holds a non-finite or out-of-range value";
  for (int i = 0; i < 4; ++i) {
    const pt::Ray r = pt::thin_lens_ray(c, rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform());
    if (!pt::is_finite(r.d)) return "a thin-lens ray from the camera is not finite";
  }
  return "";
}

std::string check_map(const pt::EnvironmentMap& env, Random& rng) {
  if (env.width < 1 || env.height < 1 || env.texels.size() != size_t(env.width) * size_t(env.height))
    return "the map's size does not match its texels";
  for (const pt::Color& c : env.texels)
    if (!pt::is_finite(c) || c.x < 0 || c.y < 0 || c.z < 0) return "a texel is negative or not finite";
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const pt::Vec3 odd[] = {{nan, nan, nan}, {inf, 0, 0}, {0, -inf, inf}, {0, 0, 0}, {1e38f, -1e38f, 1e38f}};
  for (const pt::Vec3& d : odd)
    if (!pt::is_finite(env.lookup(d))) return "a lookup returned a non-finite colour";
  for (int i = 0; i < 8; ++i) {
    const pt::Vec3 d(float(rng.uniform() * 2 - 1), float(rng.uniform() * 2 - 1), float(rng.uniform() * 2 - 1));
    env.lookup(d);
  }
  return "";
}

Outcome read_input(Kind kind, const std::string& path, Random& rng) {
  Outcome o;
  const std::string k = kind_name(kind);
  try {
    if (kind == Kind::Scene) {
      std::vector<std::string> warnings;
      const pt::Scene scene = pt::load_collada(path, &warnings);
      for (const std::string& w : warnings)
        if (!one_line_from(w, path)) o.finding = "a warning is not one line starting with the path: " + w;
      if (o.finding.empty()) o.finding = check_scene(scene);
      if (o.finding.empty()) o.finding = check_bvh(scene, rng);
      o.key = k + " loaded" + (warnings.empty() ? "" : " with warnings: " + shape(path, warnings.front()));
    } else if (kind == Kind::Camera) {
      pt::Camera cam;
      cam.load_settings(path);
      o.finding = check_camera(cam, rng);
      o.key = k + " loaded";
    } else {
      const pt::EnvironmentMap env = pt::load_environment_map(path);
      o.finding = check_map(env, rng);
      o.key = k + " loaded";
    }
  } catch (const pt::SceneError& e) {
    if (kind != Kind::Scene) o.finding = std::string("unexpected SceneError: ") + e.what();
    else if (!one_line_from(e.what(), path)) o.finding = std::string("a message not of one line naming the file: ") + e.what();
    o.key = k + " refused: " + shape(path, e.what());
  } catch (const std::runtime_error& e) {
    // Exactly std::runtime_error for the camera and the map; a SceneError
    // for scenes (caught above).
    if (kind == Kind::Scene || typeid(e) != typeid(std::runtime_error))
      o.finding = std::string("unexpected exception type ") + typeid(e).name() + ": " + e.what();
    else if (!one_line_from(e.what(), path))
      o.finding = std::string("a message not of one line naming the file: ") + e.what();
    o.key = k + " refused: " + shape(path, e.what());
  } catch (const std::exception& e) {
    o.finding = std::string("unexpected exception ") + typeid(e).name() + ": " + e.what();
    o.key = k + " threw " + typeid(e).name();
  }
  return o;
}

// ---- Seeds -------------------------------------------------------------------------

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

Kind kind_of(const fs::path& p) {
  const std::string ext = p.extension().string();
  if (ext == ".dae") return Kind::Scene;
  if (ext == ".exr") return Kind::Exr;
  return Kind::Camera;
}

// Small OpenEXR files in every compression and layout, written here so that
// the mutations reach each decoder.
void write_exr_seeds(const std::string& dir, std::vector<Seed>* seeds) {
  const int w = 12, h = 5;
  std::vector<Imf::Rgba> px(size_t(w * h));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) px[size_t(y * w + x)] = Imf::Rgba(0.1f * float(x), 0.2f * float(y), 0.5f, 1.0f);
  const std::pair<Imf::Compression, const char*> schemes[] = {
      {Imf::NO_COMPRESSION, "none"}, {Imf::RLE_COMPRESSION, "rle"},   {Imf::ZIPS_COMPRESSION, "zips"},
      {Imf::ZIP_COMPRESSION, "zip"}, {Imf::PIZ_COMPRESSION, "piz"},   {Imf::PXR24_COMPRESSION, "pxr24"},
      {Imf::B44_COMPRESSION, "b44"}, {Imf::B44A_COMPRESSION, "b44a"}, {Imf::DWAA_COMPRESSION, "dwaa"}};
  for (const auto& [c, name] : schemes) {
    const std::string path = dir + "/seed-" + name + ".exr";
    {
      Imf::RgbaOutputFile f(path.c_str(), w, h, Imf::WRITE_RGB, 1, Imath::V2f(0, 0), 1, Imf::INCREASING_Y, c);
      f.setFrameBuffer(px.data(), 1, size_t(w));
      f.writePixels(h);
    }
    seeds->push_back({std::string("generated ") + name + ".exr", Kind::Exr, slurp(path)});
  }
  {
    const std::string path = dir + "/seed-luminance.exr";
    {
      Imf::RgbaOutputFile f(path.c_str(), w, h, Imf::WRITE_Y);
      f.setFrameBuffer(px.data(), 1, size_t(w));
      f.writePixels(h);
    }
    seeds->push_back({"generated luminance.exr", Kind::Exr, slurp(path)});
  }
  {
    const std::string path = dir + "/seed-tiled.exr";
    {
      Imf::TiledRgbaOutputFile f(path.c_str(), w, h, 4, 4, Imf::MIPMAP_LEVELS, Imf::ROUND_DOWN, Imf::WRITE_RGBA);
      f.setFrameBuffer(px.data(), 1, size_t(w));
      for (int level = 0; level < f.numLevels(); ++level)
        f.writeTiles(0, f.numXTiles(level) - 1, 0, f.numYTiles(level) - 1, level);
    }
    seeds->push_back({"generated tiled.exr", Kind::Exr, slurp(path)});
  }
}

// Fixed probes of the BVH build at the edges of float that random
// mutation seldom reaches: coordinates spanning +-3e38 (extents and
// centroids overflow to infinity), one centroid shared by every triangle,
// and triangles a few denormals wide. Under the sanitizers, a bin number
// converted from NaN or infinity aborts the run here.
std::string probe_bvh_extremes() {
  const float big = 3.0e38f, tiny = 1e-42f;
  const auto scene_of = [](const std::vector<std::array<pt::Vec3, 3>>& tris) {
    pt::Scene s;
    s.materials.push_back(pt::Material{});
    for (const auto& t : tris) {
      pt::Triangle tri;
      tri.p1 = t[0], tri.p2 = t[1], tri.p3 = t[2];
      tri.n1 = tri.n2 = tri.n3 = pt::Vec3(0, 0, 1);
      s.triangles.push_back(tri);
    }
    return s;
  };
  std::vector<std::vector<std::array<pt::Vec3, 3>>> cases(3);
  for (int i = 0; i < 40; ++i) {
    const float x = (i % 2 ? big : -big) * (1.0f - 0.01f * float(i));
    cases[0].push_back({pt::Vec3(x, 0, 0), pt::Vec3(x, 1, 0), pt::Vec3(-x, 0, 1)});
    cases[1].push_back({pt::Vec3(-1, -1, 0), pt::Vec3(1, 1, 0), pt::Vec3(0, 0, float(i % 3) - 1)});
    cases[2].push_back({pt::Vec3(tiny * float(i), 0, 0), pt::Vec3(tiny * float(i + 1), 0, 0), pt::Vec3(0, tiny, 0)});
  }
  for (const auto& c : cases) {
    const pt::Scene s = scene_of(c);
    const pt::BVH bvh(s);
    pt::Ray r(pt::Vec3(0, 0, -1), pt::Vec3(0, 0, 1), 0.0f, std::numeric_limits<float>::infinity());
    pt::Hit hit;
    bvh.intersect(r, &hit);
    // Through the interface (a BVH's layout is its own): the scene's box
    // holds every primitive.
    const pt::BBox all = bvh.bounds();
    for (const pt::Triangle& t : s.triangles) {
      const pt::BBox b = t.bounds();
      if (!(all.lo.x <= b.lo.x && all.lo.y <= b.lo.y && all.lo.z <= b.lo.z && all.hi.x >= b.hi.x &&
            all.hi.y >= b.hi.y && all.hi.z >= b.hi.z))
        return "the BVH lost primitives (its bounds miss one)";
    }
  }
  return "";
}

int usage(const char* msg) {
  std::fprintf(stderr,
               "fuzz_loaders: %s\nusage: fuzz_loaders [--seed N] [--iterations N] [--seconds S] "
               "[--max-seed-bytes N] [--timeout S] [--work DIR] [--skip-without PATH] INPUT...\n",
               msg);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  uint64_t seed = 1;
  long long iterations = -1;
  double seconds = -1;
  size_t max_seed_bytes = 400000;
  unsigned timeout = 60;
  std::string work;
  std::vector<std::string> inputs, required;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
      return argv[++i];
    };
    try {
      if (a == "--seed") seed = std::stoull(value());
      else if (a == "--iterations") iterations = std::stoll(value());
      else if (a == "--seconds") seconds = std::stod(value());
      else if (a == "--max-seed-bytes") max_seed_bytes = std::stoull(value());
      else if (a == "--timeout") timeout = unsigned(std::stoul(value()));
      else if (a == "--work") work = value();
      else if (a == "--skip-without") required.push_back(value());
      else if (a.rfind("--", 0) == 0) return usage(("unknown option " + a).c_str());
      else inputs.push_back(a);
    } catch (const std::exception& e) {
      return usage(e.what());
    }
  }
  if (iterations < 0 && seconds < 0) iterations = 1000;
  // A run over optional seeds (the course's scenes) is skipped, exit code 77
  // for ctest, when they are absent: their presence adds a run of its own
  // and never changes which inputs another seeded run tries.
  for (const std::string& path : required) {
    std::error_code ec;
    if (!fs::exists(path, ec)) {
      std::printf("fuzz_loaders: skipped: %s is absent (this run mutates the files there)\n", path.c_str());
      return 77;
    }
  }
  g_seed = seed;
  __sanitizer_set_death_callback(on_sanitizer_death);
  std::set_terminate(on_terminate);
  signal(SIGALRM, on_alarm);

  bool own_work = false;
  if (work.empty()) {
    std::string tmpl = (fs::temp_directory_path() / "pt-fuzz-XXXXXX").string();
    if (!mkdtemp(tmpl.data())) return usage("cannot create a work folder");
    work = tmpl;
    own_work = true;
  }
  fs::create_directories(work);

  g_current_label = "the fixed BVH probes";
  if (const std::string finding = probe_bvh_extremes(); !finding.empty()) {
    std::fprintf(stderr, "fuzz_loaders: finding in %s: %s\n", g_current_label.c_str(), finding.c_str());
    return 1;
  }

  // Seeds: the inputs, and generated EXR files.
  std::vector<Seed> seeds;
  for (const std::string& in : inputs) {
    std::error_code ec;
    if (fs::is_directory(in, ec)) {
      std::vector<fs::path> files;
      for (const auto& e : fs::directory_iterator(in)) {
        const std::string ext = e.path().extension().string();
        if (ext == ".dae" || ext == ".exr" || ext == ".txt") files.push_back(e.path());
      }
      std::sort(files.begin(), files.end());  // a fixed order: the run depends on it
      for (const fs::path& p : files) seeds.push_back({p.filename().string(), kind_of(p), slurp(p.string())});
    } else if (fs::is_regular_file(in, ec)) {
      seeds.push_back({fs::path(in).filename().string(), kind_of(in), slurp(in)});
    } else {
      return usage((in + " does not exist").c_str());
    }
  }
  write_exr_seeds(work, &seeds);

  // Every seed must read cleanly before it is mutated.
  int findings = 0;
  Random check_rng(seed);
  std::vector<Seed> pool;
  for (const Seed& s : seeds) {
    const std::string path = work + "/seed" + kind_ext(s.kind);
    std::ofstream(path, std::ios::binary) << s.bytes;
    g_current_input = path;
    g_current_label = "seed " + s.name;
    alarm(timeout);
    const Outcome o = read_input(s.kind, path, check_rng);
    alarm(0);
    if (o.key.find(" loaded") == std::string::npos || o.key.find("warnings") != std::string::npos ||
        !o.finding.empty()) {
      std::printf("fuzz_loaders: seed %s does not read cleanly: %s %s\n", s.name.c_str(), o.key.c_str(),
                  o.finding.c_str());
      ++findings;
    }
    if (s.bytes.size() <= max_seed_bytes) pool.push_back(s);
  }
  bool have[3] = {false, false, false};
  for (const Seed& s : pool) have[int(s.kind)] = true;

  Random rng(seed);
  std::map<std::string, long long> outcomes;
  long long per_kind[3] = {0, 0, 0}, loaded[3] = {0, 0, 0};
  double kind_seconds[3] = {0, 0, 0};
  double slowest = 0;
  std::string slowest_label;
  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  long long it = 0;
  for (; iterations < 0 || it < iterations; ++it) {
    if (seconds >= 0 && elapsed() >= seconds) break;
    // Scenes most often: they have the most structure.
    const double r = rng.uniform();
    Kind kind = r < 0.6 ? Kind::Scene : r < 0.85 ? Kind::Exr : Kind::Camera;
    if (!have[int(kind)]) kind = have[0] ? Kind::Scene : have[2] ? Kind::Exr : Kind::Camera;
    std::vector<const Seed*> same;
    for (const Seed& s : pool)
      if (s.kind == kind) same.push_back(&s);
    if (same.empty()) return usage("no seed to mutate");
    const Seed& from = *same[rng.below(same.size())];
    std::string bytes = from.bytes;
    mutate(rng, bytes, kind, pool);

    const std::string path = work + "/input" + kind_ext(kind);
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
    g_current_input = path;
    g_current_label = "iteration " + std::to_string(it) + " (" + kind_name(kind) + ", from " + from.name + ")";
    const auto s0 = std::chrono::steady_clock::now();
    alarm(timeout);
    const Outcome o = read_input(kind, path, rng);
    alarm(0);
    const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - s0).count();
    if (std::getenv("PT_FUZZ_SLOW") && took > std::atof(std::getenv("PT_FUZZ_SLOW"))) {
      std::printf("fuzz_loaders: slow input: %s took %.3f s: %s\n", g_current_label.c_str(), took, o.key.c_str());
      std::error_code ec;
      fs::copy_file(path, "fuzz-slow-" + std::to_string(it) + kind_ext(kind), fs::copy_options::overwrite_existing, ec);
    }
    if (took > slowest) {
      slowest = took;
      slowest_label = g_current_label;
    }
    ++per_kind[int(kind)];
    kind_seconds[int(kind)] += took;
    if (o.key.find(" loaded") != std::string::npos) ++loaded[int(kind)];
    ++outcomes[o.key];
    if (!o.finding.empty()) {
      ++findings;
      std::printf("fuzz_loaders: FINDING at %s: %s\n", g_current_label.c_str(), o.finding.c_str());
      std::error_code ec;
      fs::copy_file(path, "fuzz-finding-" + std::to_string(it) + kind_ext(kind), fs::copy_options::overwrite_existing, ec);
    }
  }
  g_current_input.clear();
  const double total = elapsed();

  std::printf("fuzz_loaders: seed %llu: %lld inputs in %.1f s (%.0f per second): %lld scenes (%lld read, %.1f s), "
              "%lld environment maps (%lld read, %.1f s), %lld camera files (%lld read, %.1f s)\n",
              (unsigned long long)seed, it, total, total > 0 ? double(it) / total : 0.0, per_kind[0], loaded[0],
              kind_seconds[0], per_kind[2], loaded[2], kind_seconds[2], per_kind[1], loaded[1], kind_seconds[1]);
  std::printf("fuzz_loaders: %zu distinct outcomes; slowest input %.2f s (%s); %d finding%s\n", outcomes.size(),
              slowest, slowest_label.c_str(), findings, findings == 1 ? "" : "s");
  if (std::getenv("PT_FUZZ_VERBOSE"))
    for (const auto& [key, n] : outcomes) std::printf("  %6lld  %s\n", n, key.c_str());
  if (own_work && findings == 0) {
    std::error_code ec;
    fs::remove_all(work, ec);
  }
  return findings == 0 ? 0 : 1;
}
