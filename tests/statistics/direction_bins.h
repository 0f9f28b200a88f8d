// Directions binned in solid angle, with the expected count of each cell
// integrated numerically from a density: the cells of the chi-square tests
// of the sampling routines (header-only).
#pragma once
#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "common/frame.h"

namespace pt::test {

// Cells of equal extent in (cos theta, phi) about the z axis of a frame, over
// the cap cos theta in [cos_min, 1], plus one last cell for every direction
// outside the cap. Since d(omega) = d(cos theta) d(phi), the cells of one
// ring have equal solid angle.
struct DirectionBins {
  Frame frame;
  int n_cos = 16, n_phi = 32;
  double cos_min = -1.0;

  int size() const { return n_cos * n_phi + 1; }
  int outside() const { return n_cos * n_phi; }

  int cell(const Vec3& world) const {
    const Vec3 w = frame.to_local(world);
    const double len = std::sqrt(double(w.x) * w.x + double(w.y) * w.y + double(w.z) * w.z);
    const double c = w.z / len;
    if (!(c >= cos_min)) return outside();
    int i = int((c - cos_min) / (1.0 - cos_min) * n_cos);
    i = std::min(std::max(i, 0), n_cos - 1);
    double phi = std::atan2(double(w.y), double(w.x));
    if (phi < 0) phi += 2.0 * M_PI;
    int j = int(phi / (2.0 * M_PI) * n_phi);
    j = std::min(std::max(j, 0), n_phi - 1);
    return i * n_phi + j;
  }

  // The world direction at (cos theta, phi).
  Vec3 direction(double c, double phi) const {
    const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
    return frame.to_world(Vec3(float(s * std::cos(phi)), float(s * std::sin(phi)), float(c)));
  }

  // Integral of `pdf` (a density per steradian of world directions) over
  // each cell, by the midpoint rule on sub x sub sub-cells in (cos, phi).
  // With refine > 1, a sub-cell whose centre and corners disagree on
  // whether the density is zero (it straddles the edge of the support, where
  // the density jumps) is integrated on refine x refine points instead.
  // The last entry is the integral over the directions outside the cap (on
  // a grid of at most 256 x 512 points; left 0 with include_outside false).
  std::vector<double> integrate(const std::function<double(const Vec3&)>& pdf, int sub,
                                bool include_outside = true, int refine = 1) const {
    std::vector<double> mass(size_t(size()), 0.0);
    const double dc = (1.0 - cos_min) / n_cos, dp = 2.0 * M_PI / n_phi;
    const double sc = dc / sub, sp = dp / sub;
    std::vector<char> corner(size_t(sub + 1) * (sub + 1));
    for (int i = 0; i < n_cos; ++i)
      for (int j = 0; j < n_phi; ++j) {
        const double c0 = cos_min + i * dc, p0 = j * dp;
        if (refine > 1)
          for (int a = 0; a <= sub; ++a)
            for (int b = 0; b <= sub; ++b)
              corner[size_t(a) * (sub + 1) + b] = pdf(direction(std::min(1.0, c0 + a * sc), p0 + b * sp)) > 0;
        double sum = 0;
        for (int a = 0; a < sub; ++a)
          for (int b = 0; b < sub; ++b) {
            const double centre = pdf(direction(c0 + (a + 0.5) * sc, p0 + (b + 0.5) * sp));
            bool straddles = false;
            if (refine > 1) {
              const bool in = centre > 0;
              for (int k = 0; k < 4; ++k)
                straddles |= corner[size_t(a + k / 2) * (sub + 1) + b + k % 2] != in;
            }
            if (!straddles) {
              sum += centre;
              continue;
            }
            double fine = 0;
            for (int u = 0; u < refine; ++u)
              for (int v = 0; v < refine; ++v)
                fine += pdf(direction(c0 + (a + (u + 0.5) / refine) * sc, p0 + (b + (v + 0.5) / refine) * sp));
            sum += fine / (double(refine) * refine);
          }
        mass[size_t(i * n_phi + j)] = sum * sc * sp;
      }
    if (include_outside && cos_min > -1.0) {
      const int n = std::min(n_cos * sub, 256), m = 2 * n;
      const double oc = (cos_min + 1.0) / n, op = 2.0 * M_PI / m;
      double sum = 0;
      for (int a = 0; a < n; ++a)
        for (int b = 0; b < m; ++b) sum += pdf(direction(-1.0 + (a + 0.5) * oc, (b + 0.5) * op));
      mass[size_t(outside())] = sum * oc * op;
    }
    return mass;
  }
};

// Integral of a density over the whole sphere of directions (midpoint rule on
// n x 2n cells in (cos theta, phi) about +Z).
inline double integrate_sphere(const std::function<double(const Vec3&)>& pdf, int n = 400) {
  DirectionBins all;
  all.frame = Frame::from_normal(Vec3(0, 0, 1));
  all.n_cos = n;
  all.n_phi = 2 * n;
  all.cos_min = -1.0;
  double total = 0;
  for (double m : all.integrate(pdf, 1)) total += m;
  return total;
}

}  // namespace pt::test
