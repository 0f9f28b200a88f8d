#include "grader/src/signature.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace grader {

namespace {

double lum(const pt::Color& c) { return (double(c.x) + c.y + c.z) / 3.0; }

// The value below which `fraction` of `v` lies.
double quantile(std::vector<double> v, double fraction) {
  if (v.empty()) return 0;
  const size_t k = std::min(v.size() - 1, size_t(fraction * double(v.size())));
  std::nth_element(v.begin(), v.begin() + long(k), v.end());
  return v[k];
}

// Sums of candidate and reference over one region.
struct Region {
  double c = 0, m = 0;
  void add(double cv, double mv) { c += cv, m += mv; }
};

void put_ratio(Signature* s, const char* key, const Region& r, double floor) {
  if (r.m > floor) (*s)[key] = r.c / r.m;
}

}  // namespace

Signature image_signature(const ImageBuffer& cand, const ImageBuffer& ref, const ImageScore& score) {
  Signature s;
  const int w = ref.width, h = ref.height;
  const size_t n = size_t(w) * h;
  std::vector<double> L(n), grad(n, 0.0), lit;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) L[size_t(y) * w + x] = lum(ref.at(x, y));
  double total_m = 0;
  for (double v : L) total_m += v;
  const double black = 1e-4 * std::max(1e-6, total_m / double(n));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const double gx = x + 1 < w ? std::fabs(L[i + 1] - L[i]) : 0, gy = y + 1 < h ? std::fabs(L[i + w] - L[i]) : 0;
      grad[i] = std::max(gx, gy);
      if (L[i] > black) lit.push_back(L[i]);
    }
  const double bright = quantile(lit, 0.9), dark = quantile(lit, 0.3), edge = quantile(grad, 0.85);
  Region all, rb, rd, rm, re, rf, rt, rbot, rblack;
  Region grid[kGridSide][kGridSide];  // [row from the top][column]
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const double cv = lum(cand.at(x, y)), mv = L[i];
      all.add(cv, mv);
      grid[(h - 1 - y) * kGridSide / h][x * kGridSide / w].add(cv, mv);
      (y >= h / 2 ? rt : rbot).add(cv, mv);  // rows from the bottom: the upper half has large y
      if (mv <= black) {
        rblack.add(cv, mv);
        continue;
      }
      (mv >= bright ? rb : mv <= dark ? rd : rm).add(cv, mv);
      (grad[i] >= edge && edge > 0 ? re : rf).add(cv, mv);
    }
  const double floor = 1e-6 * double(n);
  put_ratio(&s, "mean_ratio", all, floor);
  put_ratio(&s, "ratio_bright", rb, floor * 0.1);
  put_ratio(&s, "ratio_dark", rd, floor * 0.1);
  put_ratio(&s, "ratio_mid", rm, floor * 0.1);
  put_ratio(&s, "ratio_edges", re, floor * 0.1);
  put_ratio(&s, "ratio_flat", rf, floor * 0.1);
  put_ratio(&s, "ratio_top", rt, floor * 0.1);
  put_ratio(&s, "ratio_bottom", rbot, floor * 0.1);
  for (int r = 0; r < kGridSide; ++r)
    for (int c = 0; c < kGridSide; ++c)
      put_ratio(&s, grid_key(r, c).c_str(), grid[r][c], floor * 0.1 / (kGridSide * kGridSide));
  if (all.m > floor) s["light_in_black"] = rblack.c / all.m;
  if (score.channels_tested > 0) s["failed_fraction"] = double(score.channels_failed) / score.channels_tested;
  if (score.noise_ratio >= 0) s["noise_ratio"] = score.noise_ratio;
  if (score.mean_tested)
    for (int c = 0; c < 3; ++c) s["mean_z_" + std::to_string(c)] = score.mean_z[c];
  return s;
}

std::string grid_key(int row, int column) {
  return "ratio_cell_" + std::to_string(row) + "_" + std::to_string(column);
}

}  // namespace grader
