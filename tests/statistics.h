// Statistical instruments for the rendering tests (header-only, no external
// libraries): the distribution functions the tests need (normal, chi-square,
// Student t, computed from the regularized incomplete gamma and beta
// functions), Sidak's correction, a chi-square goodness-of-fit test with
// pooling of sparse cells, binning of directions in solid angle with expected
// counts integrated numerically from a density, running moments, z and
// Welch t tests, and small builders for scenes made in code.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "frame.h"
#include "image.h"
#include "scene.h"

namespace pt::test {

// With PT_STATS_VERBOSE set in the environment, the tests print every
// statistic they compute (for judging power and margins by hand).
inline bool stats_verbose() { return std::getenv("PT_STATS_VERBOSE") != nullptr; }
inline void stats_log(const std::string& line) {
  if (stats_verbose()) std::cout << "  [stats] " << line << "\n";
}

// ---------------------------------------------------------------------------
// Special functions

// Regularized lower incomplete gamma P(a, x) and upper Q(a, x) = 1 - P.
// Series for x < a + 1, Lentz's continued fraction otherwise.
inline double gamma_p_series(double a, double x) {
  double term = 1.0 / a, sum = term;
  for (int n = 1; n < 100000; ++n) {
    term *= x / (a + n);
    sum += term;
    if (std::fabs(term) < std::fabs(sum) * 1e-16) break;
  }
  return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}

inline double gamma_q_fraction(double a, double x) {
  const double tiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 100000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::fabs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::fabs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::fabs(delta - 1.0) < 1e-16) break;
  }
  return h * std::exp(-x + a * std::log(x) - std::lgamma(a));
}

inline double regularized_gamma_q(double a, double x) {
  if (x <= 0) return 1.0;
  if (!std::isfinite(x)) return 0.0;
  return x < a + 1.0 ? 1.0 - gamma_p_series(a, x) : gamma_q_fraction(a, x);
}

// Regularized incomplete beta I_x(a, b), continued fraction (Lentz) on the
// side where it converges fast.
inline double beta_fraction(double a, double b, double x) {
  const double tiny = 1e-300;
  double c = 1.0, d = 1.0 - (a + b) * x / (a + 1.0);
  if (std::fabs(d) < tiny) d = tiny;
  d = 1.0 / d;
  double h = d;
  for (int m = 1; m < 100000; ++m) {
    const int m2 = 2 * m;
    double aa = m * (b - m) * x / ((a + m2 - 1.0) * (a + m2));
    d = 1.0 + aa * d;
    if (std::fabs(d) < tiny) d = tiny;
    c = 1.0 + aa / c;
    if (std::fabs(c) < tiny) c = tiny;
    d = 1.0 / d;
    h *= d * c;
    aa = -(a + m) * (a + b + m) * x / ((a + m2) * (a + m2 + 1.0));
    d = 1.0 + aa * d;
    if (std::fabs(d) < tiny) d = tiny;
    c = 1.0 + aa / c;
    if (std::fabs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::fabs(delta - 1.0) < 1e-16) break;
  }
  return h;
}

inline double regularized_beta(double a, double b, double x) {
  if (x <= 0) return 0.0;
  if (x >= 1) return 1.0;
  const double front =
      std::exp(std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log1p(-x));
  if (x < (a + 1.0) / (a + b + 2.0)) return front * beta_fraction(a, b, x) / a;
  return 1.0 - front * beta_fraction(b, a, 1.0 - x) / b;
}

// Inverts a decreasing survival function sf on [lo, hi] by bisection.
inline double invert_decreasing(const std::function<double(double)>& sf, double p, double lo, double hi) {
  for (int i = 0; i < 300; ++i) {
    const double mid = 0.5 * (lo + hi);
    (sf(mid) > p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// Standard normal: upper tail P(Z > z) and its inverse.
inline double normal_sf(double z) { return 0.5 * std::erfc(z / std::sqrt(2.0)); }
inline double normal_upper_quantile(double p) { return invert_decreasing(normal_sf, p, -40.0, 40.0); }

// Chi-square with k degrees of freedom: upper tail and upper quantile.
inline double chi2_sf(double x, double k) { return regularized_gamma_q(0.5 * k, 0.5 * x); }
inline double chi2_upper_quantile(double p, double k) {
  return invert_decreasing([k](double x) { return chi2_sf(x, k); }, p, 0.0, 100.0 * k + 1000.0);
}

// Student t with nu degrees of freedom: upper tail P(T > t).
inline double student_t_sf(double t, double nu) {
  const double tail = 0.5 * regularized_beta(0.5 * nu, 0.5, nu / (nu + t * t));
  return t >= 0 ? tail : 1.0 - tail;
}
inline double student_t_upper_quantile(double p, double nu) {
  return invert_decreasing([nu](double t) { return student_t_sf(t, nu); }, p, -1e3, 1e3);
}

// Sidak: the level of each of k independent tests for a family-wise level alpha.
inline double sidak(double alpha, int k) { return 1.0 - std::pow(1.0 - alpha, 1.0 / k); }

// ---------------------------------------------------------------------------
// Chi-square goodness of fit

struct ChiSquareResult {
  double statistic = 0;
  int dof = 0;
  double p_value = 1;
  int cells = 0;             // after pooling
  int pooled_cells = 0;      // cells with expected < min_expected merged into one
  long long impossible = 0;  // samples that fell in cells of zero expected count
  std::string describe() const {
    std::ostringstream s;
    s << "chi2 = " << statistic << " with " << dof << " dof (" << cells << " cells, " << pooled_cells
      << " sparse cells pooled), p = " << p_value;
    if (impossible > 0) s << "; " << impossible << " samples where the density is zero";
    return s.str();
  }
};

// Pearson's test of observed counts against expected counts. Cells whose
// expected count is below `min_expected` are pooled into one cell; if that
// pool is still below `min_expected` it joins the smallest remaining cell.
// With `zero_is_impossible`, samples in cells whose expected count is
// (numerically) zero make the test fail outright (p = 0); leave it off when
// the expected counts come from a discontinuous density whose support may
// graze a cell between the integration points.
inline ChiSquareResult chi_square_test(const std::vector<double>& observed, const std::vector<double>& expected,
                                       bool zero_is_impossible = true, double min_expected = 5.0) {
  ChiSquareResult r;
  double total = 0;
  for (double e : expected) total += e;
  std::vector<std::pair<double, double>> cells;  // (expected, observed)
  double pool_e = 0, pool_o = 0;
  for (size_t i = 0; i < observed.size(); ++i) {
    if (zero_is_impossible && expected[i] <= 1e-9 * total && observed[i] > 0) r.impossible += (long long)observed[i];
    if (expected[i] < min_expected) {
      pool_e += expected[i];
      pool_o += observed[i];
      ++r.pooled_cells;
    } else {
      cells.emplace_back(expected[i], observed[i]);
    }
  }
  if (pool_e > 0 || pool_o > 0) {
    if (pool_e >= min_expected || cells.empty()) {
      cells.emplace_back(pool_e, pool_o);
    } else {
      auto smallest = std::min_element(cells.begin(), cells.end());
      smallest->first += pool_e;
      smallest->second += pool_o;
    }
  }
  r.cells = int(cells.size());
  r.dof = std::max(1, r.cells - 1);
  for (const auto& c : cells) {
    if (c.first > 0)
      r.statistic += (c.second - c.first) * (c.second - c.first) / c.first;
    else if (c.second > 0)
      r.statistic = std::numeric_limits<double>::infinity();
  }
  r.p_value = r.impossible > 0 ? 0.0 : chi2_sf(r.statistic, r.dof);
  return r;
}

// ---------------------------------------------------------------------------
// Directions binned in solid angle

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

// ---------------------------------------------------------------------------
// Moments and tests of means

struct RunningStats {
  long long n = 0;
  double mean = 0, m2 = 0;
  void add(double x) {
    ++n;
    const double d = x - mean;
    mean += d / double(n);
    m2 += d * (x - mean);
  }
  double variance() const { return n > 1 ? m2 / double(n - 1) : 0.0; }
  double std_error() const { return std::sqrt(variance() / double(n)); }
};

// Two-sided z test of a sample mean against a known value.
struct ZTest {
  double z = 0, p_value = 1;
};
inline ZTest z_test(const RunningStats& s, double expected) {
  ZTest t;
  const double se = s.std_error();
  if (se > 0) {
    t.z = (s.mean - expected) / se;
    t.p_value = 2.0 * normal_sf(std::fabs(t.z));
  } else {
    t.z = s.mean == expected ? 0.0 : std::numeric_limits<double>::infinity();
    t.p_value = s.mean == expected ? 1.0 : 0.0;
  }
  return t;
}

// Welch's two-sample t test on batch means (each entry of a and b is the
// mean of one independent batch, e.g. one render with its own seed).
struct WelchTest {
  double difference = 0, std_error = 0, t = 0, dof = 0, p_value = 1;
};
inline WelchTest welch_test(const std::vector<double>& a, const std::vector<double>& b) {
  RunningStats sa, sb;
  for (double x : a) sa.add(x);
  for (double x : b) sb.add(x);
  WelchTest w;
  const double va = sa.variance() / double(sa.n), vb = sb.variance() / double(sb.n);
  w.difference = sa.mean - sb.mean;
  w.std_error = std::sqrt(va + vb);
  if (w.std_error > 0) {
    w.t = w.difference / w.std_error;
    w.dof = (va + vb) * (va + vb) /
            ((va > 0 ? va * va / double(sa.n - 1) : 0.0) + (vb > 0 ? vb * vb / double(sb.n - 1) : 0.0));
    w.p_value = 2.0 * student_t_sf(std::fabs(w.t), w.dof);
  } else {
    w.t = w.difference == 0 ? 0.0 : std::numeric_limits<double>::infinity();
    w.p_value = w.difference == 0 ? 1.0 : 0.0;
  }
  return w;
}

// One-sample t test on batch values (e.g. per-seed differences) against
// zero; p_value is the upper tail P(T > t) (evidence that the mean is > 0).
struct OneSampleT {
  double mean = 0, std_error = 0, t = 0, dof = 0, p_upper = 1;
};
inline OneSampleT t_test_positive(const std::vector<double>& x) {
  RunningStats s;
  for (double v : x) s.add(v);
  OneSampleT r;
  r.mean = s.mean;
  r.std_error = s.std_error();
  r.dof = double(s.n - 1);
  if (r.std_error > 0) {
    r.t = r.mean / r.std_error;
    r.p_upper = student_t_sf(r.t, r.dof);
  } else {
    r.t = r.mean > 0 ? std::numeric_limits<double>::infinity() : 0.0;
    r.p_upper = r.mean > 0 ? 0.0 : 1.0;
  }
  return r;
}

// ---------------------------------------------------------------------------
// Images compared block by block

// The mean over the three channels of each block x block square of pixels,
// blocks in rows from the bottom-left (partial blocks at the edges dropped).
inline std::vector<double> block_means(const ImageBuffer& img, int block) {
  const int bx = img.width / block, by = img.height / block;
  std::vector<double> means(size_t(bx) * by, 0.0);
  for (int j = 0; j < by; ++j)
    for (int i = 0; i < bx; ++i) {
      double sum = 0;
      for (int y = j * block; y < (j + 1) * block; ++y)
        for (int x = i * block; x < (i + 1) * block; ++x) {
          const Color& c = img.at(x, y);
          sum += (double(c.x) + c.y + c.z) / 3.0;
        }
      means[size_t(j) * bx + i] = sum / (double(block) * block);
    }
  return means;
}

inline double image_mean(const ImageBuffer& img) {
  double sum = 0;
  for (const Color& c : img.pixels) sum += (double(c.x) + c.y + c.z) / 3.0;
  return sum / double(img.pixels.size());
}

// Welch t tests, block by block, of two sets of renders: a[s][i] is block
// i of render s of the first kind, b[s][i] of the second (independent
// seeds). Each block's batch means are the per-seed block means.
struct BlockComparison {
  int blocks = 0, rejected = 0;
  double min_p = 1;
  std::string report;  // one line per rejected block
};
inline BlockComparison compare_blocks(const std::vector<std::vector<double>>& a,
                                      const std::vector<std::vector<double>>& b, double alpha_each) {
  BlockComparison r;
  r.blocks = int(a.front().size());
  std::ostringstream out;
  for (int i = 0; i < r.blocks; ++i) {
    std::vector<double> xa, xb;
    for (const auto& v : a) xa.push_back(v[size_t(i)]);
    for (const auto& v : b) xb.push_back(v[size_t(i)]);
    const WelchTest w = welch_test(xa, xb);
    r.min_p = std::min(r.min_p, w.p_value);
    if (w.p_value < alpha_each) {
      ++r.rejected;
      RunningStats ma, mb;
      for (double x : xa) ma.add(x);
      for (double x : xb) mb.add(x);
      out << "block " << i << ": " << ma.mean << " vs " << mb.mean << ", t = " << w.t << " (" << w.dof
          << " dof), p = " << w.p_value << "\n";
    }
  }
  r.report = out.str();
  return r;
}

// ---------------------------------------------------------------------------
// Closed forms for rectangular area lights (computed in double precision,
// independently of common/lights.h)

inline Vec3d to_d(const Vec3& v) { return Vec3d(v.x, v.y, v.z); }

// The density per steradian, at unit direction w from p, of the directions
// to a uniformly chosen point of the light's parallelogram: t^2 / (A cos)
// where the ray p + t w meets the light, on its emitting side only; 0 where
// it misses.
// Where the ray p + t w (w unit) meets the plane of the light's
// parallelogram: the distance t > 0 and the coordinates (a, b) of the point
// c + a dim_x + b dim_y; the point is on the light when |a|, |b| <= 1/2.
// Returns false when the ray is parallel to the plane or points away.
inline bool area_light_plane_hit(const Light& l, const Vec3d& p, const Vec3d& w, double* a, double* b, double* t) {
  const Vec3d c = to_d(l.position), dx = to_d(l.dim_x), dy = to_d(l.dim_y);
  const Vec3d n = normalize(cross(dx, dy));
  const double denom = dot(w, n);
  if (std::fabs(denom) < 1e-300) return false;
  *t = dot(c - p, n) / denom;
  if (!(*t > 0)) return false;
  const Vec3d q = p + w * *t - c;
  // q = a dx + b dy: solve the 2 x 2 Gram system.
  const double g11 = dot(dx, dx), g12 = dot(dx, dy), g22 = dot(dy, dy);
  const double r1 = dot(q, dx), r2 = dot(q, dy), det = g11 * g22 - g12 * g12;
  *a = (r1 * g22 - r2 * g12) / det;
  *b = (g11 * r2 - g12 * r1) / det;
  return true;
}

// The density per steradian, at direction w from p, of the directions to a
// uniformly chosen point of the light's parallelogram: t^2 / (A cos) where
// the ray p + t w meets the light, on its emitting side only; 0 where it
// misses.
inline double area_light_density(const Light& l, const Vec3& p, const Vec3& w_) {
  const Vec3d w = normalize(to_d(w_));
  double a, b, t;
  if (!area_light_plane_hit(l, to_d(p), w, &a, &b, &t)) return 0.0;
  if (std::fabs(a) > 0.5 || std::fabs(b) > 0.5) return 0.0;
  const double cos_l = -dot(w, normalize(to_d(l.direction)));
  if (!(cos_l > 0)) return 0.0;
  return t * t / (norm(cross(to_d(l.dim_x), to_d(l.dim_y))) * cos_l);
}

// The light's corners in order around the parallelogram.
inline std::vector<Vec3d> area_light_corners(const Light& l) {
  const Vec3d c = to_d(l.position), hx = to_d(l.dim_x) * 0.5, hy = to_d(l.dim_y) * 0.5;
  return {c - hx - hy, c + hx - hy, c + hx + hy, c - hx + hy};
}

// Irradiance at p (normal n) from a polygon of uniform radiance L, by
// Lambert's formula E = (L / 2) |sum_i theta_i n . (a_i x b_i) / |a_i x b_i||
// with a_i, b_i the unit vectors to consecutive vertices and theta_i the
// angle between them, after clipping the polygon to the half-space above
// the tangent plane of p (the part below sends no light to p).
inline double polygon_irradiance(std::vector<Vec3d> poly, const Vec3d& p, const Vec3d& n, double L) {
  // Sutherland-Hodgman against n . (x - p) >= 0.
  std::vector<Vec3d> clipped;
  for (size_t i = 0; i < poly.size(); ++i) {
    const Vec3d& a = poly[i];
    const Vec3d& b = poly[(i + 1) % poly.size()];
    const double da = dot(n, a - p), db = dot(n, b - p);
    if (da >= 0) clipped.push_back(a);
    if ((da >= 0) != (db >= 0)) clipped.push_back(a + (b - a) * (da / (da - db)));
  }
  if (clipped.size() < 3) return 0.0;
  double sum = 0;
  for (size_t i = 0; i < clipped.size(); ++i) {
    const Vec3d a = normalize(clipped[i] - p), b = normalize(clipped[(i + 1) % clipped.size()] - p);
    const Vec3d axb = cross(a, b);
    const double s = norm(axb);
    if (s < 1e-300) continue;
    const double theta = std::atan2(s, dot(a, b));
    sum += theta * dot(n, axb) / s;
  }
  return 0.5 * L * std::fabs(sum);
}

// Irradiance at p (normal n) from a one-sided rectangular area light of
// radiance L: zero behind the light.
inline double area_light_irradiance(const Light& l, const Vec3& p, const Vec3& n, double L) {
  if (dot(to_d(p) - to_d(l.position), to_d(l.direction)) <= 0) return 0.0;
  return polygon_irradiance(area_light_corners(l), to_d(p), normalize(to_d(n)), L);
}

// Solid angle of a planar convex polygon seen from p (sum of the triangles
// of a fan, Van Oosterom and Strackee's formula).
inline double polygon_solid_angle(const std::vector<Vec3d>& poly, const Vec3d& p) {
  double total = 0;
  for (size_t i = 1; i + 1 < poly.size(); ++i) {
    const Vec3d a = poly[0] - p, b = poly[i] - p, c = poly[i + 1] - p;
    const double la = norm(a), lb = norm(b), lc = norm(c);
    const double num = dot(a, cross(b, c));
    const double den = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la;
    total += 2.0 * std::fabs(std::atan2(num, den));
  }
  return total;
}

// ---------------------------------------------------------------------------
// Scenes built in code

inline int add_material(Scene& s, const Material& m) {
  s.materials.push_back(m);
  return int(s.materials.size()) - 1;
}
inline Material diffuse_material(const Color& albedo) {
  Material m;
  m.name = "diffuse";
  m.type = MaterialType::Diffuse;
  m.albedo = albedo;
  return m;
}
inline Material emissive_material(const Color& radiance) {
  Material m;
  m.name = "emission";
  m.type = MaterialType::Emission;
  m.albedo = Color(0.0f);
  m.emission = radiance;
  return m;
}

// The parallelogram corner, corner + e1, corner + e1 + e2, corner + e2 as two
// triangles with the flat normal `facing` (unit).
inline void add_quad(Scene& s, const Vec3& corner, const Vec3& e1, const Vec3& e2, const Vec3& facing, int material) {
  Triangle a, b;
  a.p1 = corner;
  a.p2 = corner + e1;
  a.p3 = corner + e1 + e2;
  b.p1 = corner;
  b.p2 = corner + e1 + e2;
  b.p3 = corner + e2;
  a.n1 = a.n2 = a.n3 = b.n1 = b.n2 = b.n3 = facing;
  a.material = b.material = material;
  s.triangles.push_back(a);
  s.triangles.push_back(b);
}

// A one-sided rectangular area light centred at `center`, spanning
// center +- dim_x / 2 +- dim_y / 2, emitting along `direction`.
inline Light area_light(const Vec3& center, const Vec3& dim_x, const Vec3& dim_y, const Vec3& direction,
                        const Color& radiance) {
  Light l;
  l.type = LightType::Area;
  l.position = center;
  l.dim_x = dim_x;
  l.dim_y = dim_y;
  l.direction = direction;
  l.radiance = radiance;
  return l;
}

// Adds an area light together with an emissive quad covering exactly its
// rectangle (so that hemisphere sampling sees what light sampling samples).
inline void add_area_light_with_quad(Scene& s, const Light& l) {
  const int m = add_material(s, emissive_material(l.radiance));
  add_quad(s, l.position - l.dim_x * 0.5f - l.dim_y * 0.5f, l.dim_x, l.dim_y, l.direction, m);
  s.lights.push_back(l);
}

// Points the camera from `eye` at `at` (world up +Y) with vertical field of
// view vfov_deg and an image of w x h pixels.
inline void aim_camera(Camera& cam, const Vec3d& eye, const Vec3d& at, double vfov_deg, int w, int h) {
  cam.look_at(eye, at, Vec3d(0, 1, 0));
  cam.screen_dist = h / (2.0 * std::tan(vfov_deg * M_PI / 360.0));
  cam.set_resolution(w, h);
}

// Shows a loaded scene's whole 800 x 600 course view in a w x h image (the
// renderer's -r keeps the focal length in pixels, i.e. crops the view).
inline void fit_course_view(Camera& cam, int w, int h) {
  cam.screen_dist *= double(h) / 600.0;
  cam.set_resolution(w, h);
}

}  // namespace pt::test
