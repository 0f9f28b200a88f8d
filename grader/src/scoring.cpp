#include "grader/src/scoring.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>


namespace grader {

double normal_two_sided_threshold(double p) {
  // P(|Z| > z) = erfc(z / sqrt 2); erfc decreases, so bisect.
  double lo = 0, hi = 40;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (std::erfc(mid / std::sqrt(2.0)) > p) lo = mid;
    else hi = mid;
  }
  return 0.5 * (lo + hi);
}

double sidak_level(double alpha, int n) {
  // 1 - (1 - alpha)^(1/n), written to keep precision for large n.
  return -std::expm1(std::log1p(-alpha) / std::max(n, 1));
}

int count_non_finite(const ImageBuffer& img, int* first_x, int* first_y) {
  int n = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      for (int c = 0; c < 3; ++c)
        if (!std::isfinite(value_from_top(img, x, y, c))) {
          if (n == 0 && first_x && first_y) {
            *first_x = x;
            *first_y = y;
          }
          ++n;
          break;
        }
  return n;
}

namespace {

// A deterministic reference: every channel within round-off of it.
ImageScore score_by_value(const ImageBuffer& cand, const ImageBuffer& mean, const ScoreOptions& opts) {
  ImageScore s;
  s.deterministic = true;
  const int w = cand.width, h = cand.height, nc = std::clamp(opts.channels, 1, 3);
  s.channels_tested = w * h * nc;
  s.pixel_z.assign(size_t(w) * h, 0.0f);
  double sum_c = 0, sum_m = 0, rel = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < nc; ++c) {
        const double cv = value_from_top(cand, x, y, c), mv = value_from_top(mean, x, y, c), d = cv - mv;
        const double tolerance = opts.abs_tolerance + opts.rel_tolerance * std::fabs(mv);
        if (std::fabs(d) > tolerance) ++s.channels_failed;
        s.max_abs_difference = std::max(s.max_abs_difference, std::fabs(d));
        // The error map shows |d| in units of the tolerance (1 = the limit).
        float& pz = s.pixel_z[size_t(y) * w + x];
        pz = std::max(pz, float(std::fabs(d) / tolerance));
        sum_c += cv;
        sum_m += mv;
        rel += d * d / (mv * mv + 0.01);
      }
  const double n = double(s.channels_tested);
  s.pixel_threshold = 1.0;
  s.mean_candidate = sum_c / n;
  s.mean_reference = sum_m / n;
  s.relmse = rel / n;
  s.passed = s.channels_failed <= (1.0 - opts.min_pass_fraction) * n;
  return s;
}

// The variance a candidate pixel channel is judged by: the larger of the
// reference's and its 3x3 neighbourhood mean, times 1 + 1/B, at least the
// floor. A pixel whose rare paths (a firefly, the fifth bounce alone) never
// showed in the B reference renders has its variance underestimated, often
// as 0. Neighbouring pixels see nearly the same paths, so each pixel's
// variance is taken as at least the mean over its 3x3 neighbourhood:
// conservative, and robust to such holes.
class JudgedVariance {
 public:
  JudgedVariance(const ImageBuffer& var, int nc, int runs, double floor)
      : w_(var.width), nc_(nc), inflate_(1.0 + 1.0 / std::max(runs, 1)), floor_(floor),
        v3_(size_t(var.width) * var.height * nc) {
    const int h = var.height;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w_; ++x)
        for (int c = 0; c < nc; ++c) {
          double sum = 0;
          int n = 0;
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
              const int xx = x + dx, yy = y + dy;
              if (xx < 0 || yy < 0 || xx >= w_ || yy >= h) continue;
              sum += value_from_top(var, xx, yy, c);
              ++n;
            }
          v3_[index(x, y, c)] = float(std::max(double(value_from_top(var, x, y, c)), sum / n));
        }
  }
  double inflate() const { return inflate_; }
  // sigma^2 of pixel (x, row y from the top), channel c.
  double operator()(int x, int y, int c) const { return std::max(double(v3_[index(x, y, c)]) * inflate_, floor_); }

 private:
  size_t index(int x, int y, int c) const { return (size_t(y) * w_ + x) * nc_ + c; }
  int w_, nc_;
  double inflate_, floor_;
  std::vector<float> v3_;  // rows from the top
};

// The image mean per channel: pixels are independent, so the mean
// difference's variance is the sum of the pixels' over their count^2.
// No winsorising here: clipping a skewed distribution (fireflies) would
// bias the mean of the clipped differences, and one firefly moves the
// mean of ten thousand pixels by little.
void image_mean_test(const double channel_d[3], const double channel_v[3], int nc, const ScoreOptions& opts,
                     ImageScore* s) {
  s->mean_tested = true;
  const int channels = std::min(nc, 3);
  s->mean_threshold = normal_two_sided_threshold(sidak_level(opts.mean_alpha, channels));
  for (int c = 0; c < channels; ++c) {
    const double se = std::sqrt(channel_v[c]);
    s->mean_z[c] = se > 0 ? channel_d[c] / se : 0.0;
    if (std::fabs(s->mean_z[c]) > s->mean_threshold) s->mean_failed = true;
  }
}

// Per 8x8 block and channel, from the top-left corner. Returns whether
// fewer than min_blocks_to_fail distinct blocks failed.
bool block_test(const ImageBuffer& cand, const ImageBuffer& mean, const JudgedVariance& sigma2, int nc,
                const ScoreOptions& opts, ImageScore* s) {
  const int w = cand.width, h = cand.height, bs = opts.block_size;
  const int bx = (w + bs - 1) / bs, by = (h + bs - 1) / bs;
  s->blocks_tested = bx * by * nc;
  s->block_threshold = normal_two_sided_threshold(sidak_level(opts.alpha, s->blocks_tested));
  for (int j = 0; j < by; ++j)
    for (int i = 0; i < bx; ++i) {
      bool block_off = false;
      for (int c = 0; c < nc; ++c) {
        double d = 0, v = 0;
        int count = 0;
        for (int y = j * bs; y < std::min(h, (j + 1) * bs); ++y)
          for (int x = i * bs; x < std::min(w, (i + 1) * bs); ++x) {
            // Each pixel's difference is clamped to +-3 of its standard
            // deviations (winsorised): one firefly, which the pixel test
            // already allows, cannot fail a block, while a bias shared by
            // the block's pixels passes through nearly unchanged.
            const double s2 = sigma2(x, y, c), limit = opts.block_clamp * std::sqrt(s2);
            d += std::clamp(double(value_from_top(cand, x, y, c)) - value_from_top(mean, x, y, c), -limit, limit);
            v += s2;
            ++count;
          }
        // Pixels are independent (each has its own random stream), so the
        // block mean's variance is the sum of theirs over count^2.
        const double se = std::sqrt(v) / count;
        const double z = std::fabs(d / count) / se;
        s->max_block_z = std::max(s->max_block_z, z);
        if (z > s->block_threshold) {
          ++s->blocks_failed;
          block_off = true;
        }
      }
      s->distinct_blocks_failed += block_off;
    }
  // A bias spread over a region fails many blocks; one block alone is
  // what a single firefly does where it dominates its block's variance
  // (the calibration found exactly that: one block, all three channels,
  // in 2 % of correct renders of some cases).
  return s->distinct_blocks_failed < opts.min_blocks_to_fail;
}

}  // namespace

ImageScore score_image(const ImageBuffer& cand, const ImageBuffer& mean, const ImageBuffer& var, int runs,
                       const ScoreOptions& opts) {
  if (opts.deterministic) return score_by_value(cand, mean, opts);
  ImageScore s;
  const int w = cand.width, h = cand.height, nc = std::clamp(opts.channels, 1, 3);
  const JudgedVariance sigma2(var, nc, runs, opts.variance_floor);

  // Per pixel channel, with the sums the image mean and relMSE need.
  s.channels_tested = w * h * nc;
  s.pixel_threshold = normal_two_sided_threshold(sidak_level(opts.alpha, s.channels_tested));
  s.pixel_z.assign(size_t(w) * h, 0.0f);
  double sum_c = 0, sum_m = 0, rel = 0, rel_expected = 0;
  double channel_d[3] = {0, 0, 0}, channel_v[3] = {0, 0, 0};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < nc; ++c) {
        const double cv = value_from_top(cand, x, y, c), mv = value_from_top(mean, x, y, c), d = cv - mv;
        channel_d[c] += d;
        channel_v[c] += sigma2(x, y, c);
        const double z = std::max(0.0, std::fabs(d) - opts.pixel_slack) / std::sqrt(sigma2(x, y, c));
        if (z > s.pixel_threshold) ++s.channels_failed;
        float& pz = s.pixel_z[size_t(y) * w + x];
        pz = std::max(pz, float(z));
        sum_c += cv;
        sum_m += mv;
        const double denom = mv * mv + 0.01;
        rel += d * d / denom;
        rel_expected += double(value_from_top(var, x, y, c)) * sigma2.inflate() / denom;
      }
  const double n = double(s.channels_tested);
  s.mean_candidate = sum_c / n;
  s.mean_reference = sum_m / n;
  s.relmse = rel / n;
  s.relmse_expected = rel_expected / n;
  const bool pixels_ok = s.channels_failed <= (1.0 - opts.min_pass_fraction) * n;

  if (opts.mean_test) image_mean_test(channel_d, channel_v, nc, opts, &s);
  const bool blocks_ok = !opts.block_test || block_test(cand, mean, sigma2, nc, opts, &s);
  s.passed = pixels_ok && blocks_ok && !s.mean_failed;
  return s;
}

double ImageScore::max_mean_z() const {
  double z = 0;
  for (double v : mean_z) z = std::max(z, std::fabs(v));
  return z;
}

std::string ImageScore::summary() const {
  char buf[240];
  const double ok = channels_tested ? 100.0 * (channels_tested - channels_failed) / channels_tested : 0.0;
  if (deterministic) {
    std::snprintf(buf, sizeof buf, "%.2f%% px within round-off, largest difference %.2g", ok, max_abs_difference);
    return buf;
  }
  std::string s;
  std::snprintf(buf, sizeof buf, "%.2f%% px ok", ok);
  s = buf;
  if (blocks_tested > 0) {
    std::snprintf(buf, sizeof buf, ", %d/%d blocks off", blocks_failed, blocks_tested);
    s += buf;
  }
  if (mean_tested) {
    std::snprintf(buf, sizeof buf, ", image mean |z| %.1f", max_mean_z());
    s += buf;
  }
  std::snprintf(buf, sizeof buf, ", relMSE %.3g (noise %.3g)", relmse, relmse_expected);
  return s + buf;
}

}  // namespace grader
