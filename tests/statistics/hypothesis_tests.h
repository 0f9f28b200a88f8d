// Hypothesis tests for the rendering tests (header-only): a chi-square
// goodness-of-fit test with pooling of sparse cells, running moments, z,
// Welch and one-sample t tests, and images compared block by block.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "common/image.h"
#include "tests/statistics/special_functions.h"

namespace pt::test {

// With PT_STATS_VERBOSE set in the environment, the tests print every
// statistic they compute (for judging power and margins by hand).
inline bool stats_verbose() { return std::getenv("PT_STATS_VERBOSE") != nullptr; }
inline void stats_log(const std::string& line) {
  if (stats_verbose()) std::cout << "  [stats] " << line << "\n";
}

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

}  // namespace pt::test
