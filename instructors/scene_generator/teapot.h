// The Utah (Newell) teapot, tessellated by the generator from its bicubic
// Bezier patches: 32 patches of 4 x 4 control points (rim, body, handle,
// spout, lid and the later-added bottom). The control points and patch
// indices are read as plain numbers from a pinned copy of a JavaScript file
// that lists them as two array literals (see sources.txt); nothing else of
// that file is used.
#pragma once
#include <array>
#include <cctype>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "instructors/scene_generator/mesh_tools.h"

namespace scenegen {

struct BezierPatchSet {
  std::vector<V3> control;                  // control points (data is Z up)
  std::vector<std::array<int, 16>> patches; // 4 x 4 control point indices, row by row
};

// The numbers of the array literal that follows `name = [` in `text`
// (comments skipped; a '-' may be separated from its number by spaces, as
// the source writes "- 0.784").
inline std::vector<double> js_number_array(const std::string& text, const std::string& name,
                                           const std::string& what) {
  const size_t at = text.find(name);
  if (at == std::string::npos) throw std::runtime_error(what + ": no array " + name);
  size_t i = text.find('[', at);
  if (i == std::string::npos) throw std::runtime_error(what + ": no '[' after " + name);
  ++i;
  std::vector<double> out;
  bool negative = false;
  while (i < text.size()) {
    const char ch = text[i];
    if (ch == ']') return out;
    if (ch == '/' && i + 1 < text.size() && text[i + 1] == '*') {
      const size_t e = text.find("*/", i + 2);
      if (e == std::string::npos) break;
      i = e + 2;
    } else if (ch == '/' && i + 1 < text.size() && text[i + 1] == '/') {
      while (i < text.size() && text[i] != '\n') ++i;
    } else if (ch == '-') {
      negative = !negative;
      ++i;
    } else if (std::isdigit(static_cast<unsigned char>(ch)) || ch == '.') {
      char* e = nullptr;
      const double d = std::strtod(text.c_str() + i, &e);
      i = size_t(e - text.c_str());
      out.push_back(negative ? -d : d);
      negative = false;
    } else if (ch == ',' || std::isspace(static_cast<unsigned char>(ch))) {
      ++i;
    } else {
      throw std::runtime_error(what + ": unexpected character in array " + name);
    }
  }
  throw std::runtime_error(what + ": array " + name + " is not closed");
}

inline BezierPatchSet read_teapot_patches(const std::string& js_text, const std::string& what) {
  const std::vector<double> idx = js_number_array(js_text, "teapotPatches", what);
  const std::vector<double> pts = js_number_array(js_text, "teapotVertices", what);
  if (idx.size() != 32 * 16 || pts.empty() || pts.size() % 3 != 0)
    throw std::runtime_error(what + ": expected 32 patches of 16 indices and xyz control points");
  BezierPatchSet s;
  for (size_t i = 0; i < pts.size(); i += 3) s.control.push_back({pts[i], pts[i + 1], pts[i + 2]});
  for (size_t p = 0; p < 32; ++p) {
    std::array<int, 16> patch{};
    for (size_t k = 0; k < 16; ++k) {
      const double d = idx[16 * p + k];
      if (d < 0 || d != double(int(d)) || size_t(d) >= s.control.size())
        throw std::runtime_error(what + ": bad control point index");
      patch[k] = int(d);
    }
    s.patches.push_back(patch);
  }
  return s;
}

inline void bernstein3(double t, double b[4]) {
  const double s = 1.0 - t;
  b[0] = s * s * s;
  b[1] = 3 * t * s * s;
  b[2] = 3 * t * t * s;
  b[3] = t * t * t;
}

// Tessellates every patch into an n x n grid of quads (two triangles each),
// welds the points the patches share along their edges and at the two poles,
// and drops the triangles that collapse there. Triangles are wound so that
// (p1 - p0) x (p2 - p0) points along dP/du x dP/dv of the patch, u running
// down the rows of its control points and v along them.
inline IndexedMesh tessellate_patches(const BezierPatchSet& s, int n) {
  IndexedMesh m;
  for (const auto& patch : s.patches) {
    const int base = int(m.v.size());
    for (int i = 0; i <= n; ++i) {
      double bu[4];
      bernstein3(double(i) / n, bu);
      for (int j = 0; j <= n; ++j) {
        double bv[4];
        bernstein3(double(j) / n, bv);
        V3 p{};
        for (int r = 0; r < 4; ++r)
          for (int c = 0; c < 4; ++c) p = p + (bu[r] * bv[c]) * s.control[size_t(patch[size_t(4 * r + c)])];
        m.v.push_back(p);
      }
    }
    auto at = [&](int i, int j) { return base + i * (n + 1) + j; };
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        m.t.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
        m.t.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
      }
  }
  // The data spans about 6 units; points computed twice along a shared edge
  // agree to ~1e-15, distinct grid points are more than 1e-3 apart.
  return weld_within(m, 1e-9, nullptr);
}

}  // namespace scenegen
