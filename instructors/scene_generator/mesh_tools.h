// Indexed triangle meshes for the generator: reading the source formats
// (OFF, ASCII PLY), welding duplicate vertices, topology and orientation
// checks, and simple transforms. Everything is deterministic: results depend
// only on the input's order, never on hashing or addresses.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <map>
#include <stdexcept>
#include <string>
#include <tuple>
#include <unordered_map>
#include <vector>

#include "common/math_constants.h"
#include "instructors/scene_generator/scene_model.h"

namespace scenegen {

using Tri = std::array<int, 3>;

struct IndexedMesh {
  std::vector<V3> v;
  std::vector<Tri> t;
};

// ---------------------------------------------------------------------------
// Reading

// A cursor over a text buffer that reads whitespace-separated numbers.
// Parsing uses strtod/strtol in the "C" locale (the generator never changes
// the locale).
class TextCursor {
 public:
  TextCursor(const std::string& text, std::string what)
      : begin_(text.c_str()), p_(begin_), end_(begin_ + text.size()), what_(std::move(what)) {}

  bool at_end() {
    skip_space();
    return p_ >= end_;
  }
  // The rest of the current line (without the newline), advancing past it.
  std::string line() {
    const char* s = p_;
    while (p_ < end_ && *p_ != '\n') ++p_;
    std::string r(s, p_);
    if (p_ < end_) ++p_;
    if (!r.empty() && r.back() == '\r') r.pop_back();
    return r;
  }
  double real() {
    skip_space();
    char* e = nullptr;
    const double d = std::strtod(p_, &e);
    if (e == p_ || !std::isfinite(d)) fail("expected a number");
    p_ = e;
    return d;
  }
  long integer() {
    skip_space();
    char* e = nullptr;
    const long v = std::strtol(p_, &e, 10);
    if (e == p_) fail("expected an integer");
    p_ = e;
    return v;
  }
  void skip_rest_of_line() {
    while (p_ < end_ && *p_ != '\n') ++p_;
  }
  [[noreturn]] void fail(const std::string& msg) const {
    throw std::runtime_error(what_ + ": " + msg + " near byte " + std::to_string(p_ - begin_));
  }

 private:
  void skip_space() {
    while (p_ < end_) {
      if (*p_ == '#') {  // OFF comments run to the end of the line
        while (p_ < end_ && *p_ != '\n') ++p_;
      } else if (*p_ == ' ' || *p_ == '\t' || *p_ == '\n' || *p_ == '\r') {
        ++p_;
      } else {
        break;
      }
    }
  }
  const char* begin_;
  const char* p_;
  const char* end_;
  std::string what_;
};

inline void add_polygon(IndexedMesh& m, const std::vector<int>& poly, size_t nverts, const TextCursor& c) {
  if (poly.size() < 3) c.fail("a face with fewer than 3 vertices");
  for (int i : poly)
    if (i < 0 || static_cast<size_t>(i) >= nverts) c.fail("a face index out of range");
  for (size_t k = 1; k + 1 < poly.size(); ++k) m.t.push_back({poly[0], poly[k], poly[k + 1]});
}

// OFF: "OFF", then vertex, face and edge counts, the vertices, then one face
// per line ("n i0 i1 ... [colour]"). Polygons are fan-triangulated.
inline IndexedMesh read_off(const std::string& text, const std::string& what) {
  TextCursor c(text, what);
  const std::string magic = c.line();
  if (magic.rfind("OFF", 0) != 0) c.fail("not an OFF file");
  const long nv = c.integer(), nf = c.integer();
  c.integer();  // edges (unused)
  if (nv <= 0 || nf <= 0) c.fail("bad counts");
  IndexedMesh m;
  m.v.reserve(size_t(nv));
  for (long i = 0; i < nv; ++i) {
    const double x = c.real(), y = c.real(), z = c.real();
    m.v.push_back({x, y, z});
  }
  std::vector<int> poly;
  for (long f = 0; f < nf; ++f) {
    const long n = c.integer();
    poly.clear();
    for (long k = 0; k < n; ++k) poly.push_back(int(c.integer()));
    c.skip_rest_of_line();  // optional colour
    add_polygon(m, poly, m.v.size(), c);
  }
  return m;
}

// ASCII PLY with a "vertex" element (float properties, x y z among them)
// followed by a "face" element with one list property.
inline IndexedMesh read_ply_ascii(const std::string& text, const std::string& what) {
  TextCursor c(text, what);
  if (c.line() != "ply") c.fail("not a PLY file");
  long nv = -1, nf = -1;
  int vprops = 0, ix = -1, iy = -1, iz = -1;
  std::string element;
  bool ascii = false;
  for (;;) {
    if (c.at_end()) c.fail("no end_header");
    const std::string l = c.line();
    if (l == "end_header") break;
    std::vector<std::string> w;
    for (size_t i = 0; i < l.size();) {
      while (i < l.size() && l[i] == ' ') ++i;
      size_t j = i;
      while (j < l.size() && l[j] != ' ') ++j;
      if (j > i) w.push_back(l.substr(i, j - i));
      i = j;
    }
    if (w.empty() || w[0] == "comment" || w[0] == "obj_info") continue;
    if (w[0] == "format") {
      ascii = w.size() >= 2 && w[1] == "ascii";
    } else if (w[0] == "element" && w.size() == 3) {
      element = w[1];
      const long n = std::strtol(w[2].c_str(), nullptr, 10);
      if (element == "vertex") nv = n;
      else if (element == "face") nf = n;
      else c.fail("unsupported element " + element);
    } else if (w[0] == "property" && element == "vertex") {
      if (w.size() != 3 || w[1] == "list") c.fail("unsupported vertex property");
      if (w[2] == "x") ix = vprops;
      if (w[2] == "y") iy = vprops;
      if (w[2] == "z") iz = vprops;
      ++vprops;
    } else if (w[0] == "property" && element == "face") {
      if (w.size() != 5 || w[1] != "list") c.fail("unsupported face property");
    }
  }
  if (!ascii || nv <= 0 || nf <= 0 || ix < 0 || iy < 0 || iz < 0) c.fail("unsupported PLY header");
  IndexedMesh m;
  m.v.reserve(size_t(nv));
  std::vector<double> props(size_t(vprops), 0.0);
  for (long i = 0; i < nv; ++i) {
    for (double& p : props) p = c.real();
    m.v.push_back({props[size_t(ix)], props[size_t(iy)], props[size_t(iz)]});
  }
  std::vector<int> poly;
  m.t.reserve(size_t(nf));
  for (long f = 0; f < nf; ++f) {
    const long n = c.integer();
    poly.clear();
    for (long k = 0; k < n; ++k) poly.push_back(int(c.integer()));
    add_polygon(m, poly, m.v.size(), c);
  }
  return m;
}

// ---------------------------------------------------------------------------
// Cleaning

// Keeps only the vertices some triangle uses, in their original order.
inline IndexedMesh drop_unused_vertices(const IndexedMesh& in) {
  std::vector<int> map(in.v.size(), -1);
  for (const Tri& t : in.t)
    for (int i : t) map[size_t(i)] = 0;
  IndexedMesh out;
  for (size_t i = 0; i < in.v.size(); ++i)
    if (map[i] == 0) {
      map[i] = int(out.v.size());
      out.v.push_back(in.v[i]);
    }
  out.t.reserve(in.t.size());
  for (const Tri& t : in.t) out.t.push_back({map[size_t(t[0])], map[size_t(t[1])], map[size_t(t[2])]});
  return out;
}

// Replaces every vertex by representative[vertex], drops the triangles that
// collapse (two equal indices) and the vertices no longer used.
inline IndexedMesh apply_vertex_map(const IndexedMesh& in, const std::vector<int>& rep, size_t* collapsed) {
  IndexedMesh m;
  m.v = in.v;
  size_t n = 0;
  for (const Tri& t : in.t) {
    const Tri r{rep[size_t(t[0])], rep[size_t(t[1])], rep[size_t(t[2])]};
    if (r[0] == r[1] || r[1] == r[2] || r[0] == r[2]) {
      ++n;
      continue;
    }
    m.t.push_back(r);
  }
  if (collapsed) *collapsed = n;
  return drop_unused_vertices(m);
}

// Merges vertices with bit-identical positions (scanned meshes often repeat
// a vertex along the seams of their range images). The first occurrence is
// kept.
inline IndexedMesh weld_exact(const IndexedMesh& in, size_t* collapsed = nullptr) {
  std::map<std::tuple<double, double, double>, int> first;
  std::vector<int> rep(in.v.size());
  for (size_t i = 0; i < in.v.size(); ++i) {
    const auto key = std::make_tuple(in.v[i].x, in.v[i].y, in.v[i].z);
    rep[i] = first.emplace(key, int(i)).first->second;
  }
  return apply_vertex_map(in, rep, collapsed);
}

// Merges vertices closer than `eps` (per coordinate) to an earlier vertex,
// e.g. the points two patches compute independently along a shared edge.
inline IndexedMesh weld_within(const IndexedMesh& in, double eps, size_t* collapsed = nullptr) {
  using Cell = std::tuple<int64_t, int64_t, int64_t>;
  std::map<Cell, std::vector<int>> grid;
  auto cell_of = [&](const V3& p) {
    return Cell{int64_t(std::floor(p.x / eps)), int64_t(std::floor(p.y / eps)), int64_t(std::floor(p.z / eps))};
  };
  std::vector<int> rep(in.v.size());
  for (size_t i = 0; i < in.v.size(); ++i) {
    const V3 p = in.v[i];
    const Cell c = cell_of(p);
    int found = -1;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          auto it = grid.find(Cell{std::get<0>(c) + dx, std::get<1>(c) + dy, std::get<2>(c) + dz});
          if (it == grid.end()) continue;
          for (int j : it->second) {
            const V3 q = in.v[size_t(j)];
            if (std::fabs(p.x - q.x) <= eps && std::fabs(p.y - q.y) <= eps && std::fabs(p.z - q.z) <= eps &&
                (found < 0 || j < found))
              found = j;
          }
        }
    if (found >= 0) {
      rep[i] = found;
    } else {
      rep[i] = int(i);
      grid[c].push_back(int(i));
    }
  }
  return apply_vertex_map(in, rep, collapsed);
}

// Undoes welds that pinch a closed surface: a vertex whose triangles form
// more than one fan (two sheets touching at a point, which merging equal
// positions can produce) gets a separate copy, at the same position, for
// each fan after the first, so that each sheet keeps its own smooth normal.
// Expects a closed, consistently wound, edge-manifold mesh.
inline IndexedMesh split_pinched_vertices(const IndexedMesh& in, size_t* split = nullptr) {
  IndexedMesh m = in;
  std::vector<std::vector<int>> around(in.v.size());
  for (size_t i = 0; i < in.t.size(); ++i)
    for (int k : in.t[i]) around[size_t(k)].push_back(int(i));
  size_t copies = 0;
  for (size_t v = 0; v < in.v.size(); ++v) {
    const std::vector<int>& tris = around[v];
    // Each triangle (v, a, b), in its winding order, links a to b.
    std::map<int, std::pair<int, int>> next;  // a -> (b, triangle)
    for (int ti : tris) {
      const Tri& t = in.t[size_t(ti)];
      const int k = t[0] == int(v) ? 0 : t[1] == int(v) ? 1 : 2;
      if (!next.emplace(t[size_t((k + 1) % 3)], std::make_pair(t[size_t((k + 2) % 3)], ti)).second)
        throw std::runtime_error("split_pinched_vertices: the mesh is not edge-manifold");
    }
    std::map<int, int> fan_of;  // triangle -> fan number
    int fans = 0;
    for (int ti : tris) {
      if (fan_of.count(ti)) continue;
      const Tri& t = in.t[size_t(ti)];
      const int k = t[0] == int(v) ? 0 : t[1] == int(v) ? 1 : 2;
      const int start = t[size_t((k + 1) % 3)];
      int a = start;
      do {
        const auto it = next.find(a);
        if (it == next.end()) throw std::runtime_error("split_pinched_vertices: the mesh is not closed");
        fan_of[it->second.second] = fans;
        a = it->second.first;
      } while (a != start);
      ++fans;
    }
    for (int f = 1; f < fans; ++f) {
      const int copy = int(m.v.size());
      m.v.push_back(in.v[v]);
      for (int ti : tris)
        if (fan_of[ti] == f)
          for (int& k : m.t[size_t(ti)])
            if (k == int(v)) k = copy;
      ++copies;
    }
  }
  if (split) *split = copies;
  return m;
}

// ---------------------------------------------------------------------------
// Checks

struct Topology {
  size_t edges = 0;
  size_t boundary_edges = 0;     // used by one triangle
  size_t nonmanifold_edges = 0;  // used by more than two
  size_t misoriented_edges = 0;  // used twice in the same direction
  size_t duplicate_triangles = 0;
  // Closed and consistently wound: every edge is used by exactly two
  // triangles, once in each direction.
  bool closed() const {
    return boundary_edges == 0 && nonmanifold_edges == 0 && misoriented_edges == 0 && duplicate_triangles == 0;
  }
};

inline Topology topology(const IndexedMesh& m) {
  std::vector<std::pair<uint64_t, int>> e;  // undirected key, +1 if a < b else -1
  e.reserve(3 * m.t.size());
  for (const Tri& t : m.t)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = uint32_t(t[size_t(k)]), b = uint32_t(t[size_t((k + 1) % 3)]);
      e.push_back({(uint64_t(std::min(a, b)) << 32) | std::max(a, b), a < b ? 1 : -1});
    }
  std::sort(e.begin(), e.end());
  Topology r;
  for (size_t i = 0; i < e.size();) {
    size_t j = i;
    int sum = 0;
    while (j < e.size() && e[j].first == e[i].first) sum += e[j++].second;
    ++r.edges;
    const size_t n = j - i;
    if (n == 1) ++r.boundary_edges;
    else if (n > 2) ++r.nonmanifold_edges;
    else if (sum != 0) ++r.misoriented_edges;
    i = j;
  }
  std::vector<Tri> s(m.t);
  for (Tri& t : s) std::sort(t.begin(), t.end());
  std::sort(s.begin(), s.end());
  for (size_t i = 1; i < s.size(); ++i)
    if (s[i] == s[i - 1]) ++r.duplicate_triangles;
  return r;
}

// Signed volume enclosed by the triangles (positive when a closed mesh is
// wound counter-clockwise seen from outside).
inline double signed_volume(const IndexedMesh& m) {
  double v = 0;
  for (const Tri& t : m.t) v += dot(m.v[size_t(t[0])], cross(m.v[size_t(t[1])], m.v[size_t(t[2])]));
  return v / 6.0;
}

struct Box3 {
  V3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  void add(V3 p) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  V3 center() const { return 0.5 * (lo + hi); }
  V3 extent() const { return hi - lo; }
};

inline Box3 bounds(const IndexedMesh& m) {
  Box3 b;
  for (const Tri& t : m.t)
    for (int i : t) b.add(m.v[size_t(i)]);
  return b;
}

// ---------------------------------------------------------------------------
// Transforms

// Rotation about +Y by `degrees` (right-handed: +X turns toward -Z).
inline V3 rotate_y(V3 p, double degrees) {
  const double a = degrees * pt::kPiDouble / 180.0;
  const double c = std::cos(a), s = std::sin(a);
  // Exact for the quarter turns used most, so they add no rounding noise.
  if (std::fmod(degrees, 90.0) == 0.0) {
    const int q = ((int(degrees / 90.0) % 4) + 4) % 4;
    const double cs[4][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
    return {cs[q][0] * p.x + cs[q][1] * p.z, p.y, -cs[q][1] * p.x + cs[q][0] * p.z};
  }
  return {c * p.x + s * p.z, p.y, -s * p.x + c * p.z};
}

// Rotates `m` about +Y, then scales it uniformly so that its bounding box
// has the given size along `axis` (0 x, 1 y, 2 z), centres it on x = z = 0
// and puts its lowest point at height `bottom_y`.
inline void place_on_floor(IndexedMesh& m, double rotate_y_degrees, int axis, double size, double bottom_y) {
  for (V3& p : m.v) p = rotate_y(p, rotate_y_degrees);
  const Box3 b = bounds(m);
  const V3 e = b.extent();
  const double have = axis == 0 ? e.x : axis == 1 ? e.y : e.z;
  const double s = size / have;
  const V3 c = b.center();
  for (V3& p : m.v) p = V3{s * (p.x - c.x), s * (p.y - b.lo.y) + bottom_y, s * (p.z - c.z)};
}

// Scales `m` uniformly so that its largest bounding-box side is `size` and
// centres the box on the origin.
inline void center_and_fit(IndexedMesh& m, double size) {
  const Box3 b = bounds(m);
  const V3 e = b.extent();
  const double s = size / std::max(e.x, std::max(e.y, e.z));
  const V3 c = b.center();
  for (V3& p : m.v) p = s * (p - c);
}

inline void reverse_winding(IndexedMesh& m) {
  for (Tri& t : m.t) std::swap(t[1], t[2]);
}

}  // namespace scenegen
