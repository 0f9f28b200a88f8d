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

double level_for_at_least(double alpha, int n, int at_least) {
  // P(k or more of n fail) <= C(n, k) p^k, so p = (alpha / C(n, k))^(1/k);
  // k = 1 is the union bound (about Sidak's level).
  const int k = std::clamp(at_least, 1, std::max(n, 1));
  double log_choose = 0;
  for (int i = 0; i < k; ++i) log_choose += std::log(double(n - i)) - std::log(double(i + 1));
  return std::min(1.0, std::exp((std::log(alpha) - log_choose) / k));
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

// A per-pixel-channel field (rows from the top), pooled: each value taken
// as at least the mean over its 3x3 neighbourhood. A pixel whose rare
// paths (a firefly, the fifth bounce alone) never showed in the renders
// that estimated its variance has it underestimated, often as 0;
// neighbouring pixels see nearly the same paths, so the pooled value is a
// conservative repair, and it gives a variance estimated from few renders
// nine times the degrees of freedom.
class ChannelField {
 public:
  ChannelField(int w, int h, int nc) : w_(w), h_(h), nc_(nc), v_(size_t(w) * h * nc, 0.0) {}
  double& operator()(int x, int y, int c) { return v_[index(x, y, c)]; }
  double operator()(int x, int y, int c) const { return v_[index(x, y, c)]; }
  ChannelField pooled() const {
    ChannelField out(w_, h_, nc_);
    for (int y = 0; y < h_; ++y)
      for (int x = 0; x < w_; ++x)
        for (int c = 0; c < nc_; ++c) {
          double sum = 0;
          int n = 0;
          for (int yy = std::max(0, y - 1); yy <= std::min(h_ - 1, y + 1); ++yy)
            for (int xx = std::max(0, x - 1); xx <= std::min(w_ - 1, x + 1); ++xx) {
              sum += (*this)(xx, yy, c);
              ++n;
            }
          out(x, y, c) = std::max((*this)(x, y, c), sum / n);
        }
    return out;
  }

 private:
  size_t index(int x, int y, int c) const { return (size_t(y) * w_ + x) * nc_ + c; }
  int w_, h_, nc_;
  std::vector<double> v_;
};

// What the tests need of the candidate and the reference, per pixel
// channel (rows from the top): the difference c - m, the variance it is
// judged by, and the raw variances behind it (relMSE, noise ratio).
struct Differences {
  int w, h, nc, renders;
  ChannelField d, sigma2, expected, candidate_case_var, reference_var;
  Differences(int w_, int h_, int nc_)
      : w(w_), h(h_), nc(nc_), renders(1), d(w_, h_, nc_), sigma2(w_, h_, nc_), expected(w_, h_, nc_),
        candidate_case_var(w_, h_, nc_), reference_var(w_, h_, nc_) {}
};

double noise_ratio(const Differences& D, const ScoreOptions& opts, double cap);

Differences differences(const CandidateRenders& cand, const ImageBuffer& mean, const ImageBuffer& var, int runs,
                        const ScoreOptions& opts) {
  const int w = mean.width, h = mean.height, nc = std::clamp(opts.channels, 1, 3);
  const int k = int(cand.images.size());
  Differences D(w, h, nc);
  D.renders = k;
  ChannelField u(w, h, nc), raw_u(w, h, nc);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < nc; ++c) {
        // Two passes over the renders: their mean, then their spread.
        double sum = 0;
        for (const ImageBuffer& img : cand.images) sum += value_from_top(img, x, y, c);
        const double cbar = sum / k;
        double ss = 0;
        for (const ImageBuffer& img : cand.images) {
          const double e = value_from_top(img, x, y, c) - cbar;
          ss += e * e;
        }
        const double s2 = k > 1 ? ss / (k - 1) : 0.0;
        D.d(x, y, c) = cbar - value_from_top(mean, x, y, c);
        D.reference_var(x, y, c) = value_from_top(var, x, y, c);
        u(x, y, c) = s2 / k;  // the variance of the renders' mean
        D.candidate_case_var(x, y, c) = s2 * cand.share;
      }
  const ChannelField vr = D.reference_var.pooled();
  const double b = std::max(runs, 1);
  if (k > 1) {
    const ChannelField pu = u.pooled();
    // Where light is found by rare hits (a small light by hemisphere
    // sampling, a long path through roulette at a low probability), most
    // pixels of four renders hold none: their spread, even pooled over
    // 3x3, says "no noise" while the estimator is very noisy there. The
    // floor is the variance the build's noise level predicts: the
    // reference's variance at that pixel (where noise is) times the build's
    // own ratio over the whole image (how much of it), per render of its
    // share. A build as noisy as the reference gets about its own spread.
    // Uncapped: here a rare large value is the very evidence of the noise.
    const double ratio = noise_ratio(D, opts, HUGE_VAL);
    const double model = ratio > 0 ? ratio / (cand.share * k) : 0.0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < nc; ++c) {
          const double own = std::max(pu(x, y, c), model * vr(x, y, c));
          D.sigma2(x, y, c) = std::max(own + vr(x, y, c) / b, opts.variance_floor);
          D.expected(x, y, c) = u(x, y, c) + D.reference_var(x, y, c) / b;
        }
  } else {
    // One render: the reference's variance stands in for the candidate's.
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < nc; ++c) {
          D.sigma2(x, y, c) = std::max(vr(x, y, c) * (1.0 + 1.0 / b), opts.variance_floor);
          D.expected(x, y, c) = D.reference_var(x, y, c) * (1.0 + 1.0 / b);
        }
  }
  return D;
}

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
    const double z = opts.upper_only ? s->mean_z[c] : std::fabs(s->mean_z[c]);
    if (z > s->mean_threshold) s->mean_failed = true;
  }
}

// Per 8x8 block and channel, from the top-left corner. Returns whether
// fewer than min_blocks_to_fail distinct blocks failed.
bool block_test(const Differences& D, const ScoreOptions& opts, ImageScore* s) {
  const int w = D.w, h = D.h, nc = D.nc, bs = opts.block_size;
  const int bx = (w + bs - 1) / bs, by = (h + bs - 1) / bs;
  s->blocks_tested = bx * by * nc;
  // A block fails when any of its channels does (Sidak over them), and
  // the image when min_blocks_to_fail distinct blocks do.
  const double block_level = level_for_at_least(opts.block_alpha, bx * by, opts.min_blocks_to_fail);
  s->block_threshold = normal_two_sided_threshold(sidak_level(block_level, nc));
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
            const double s2 = D.sigma2(x, y, c), limit = opts.block_clamp * std::sqrt(s2);
            d += std::clamp(D.d(x, y, c), -limit, limit);
            v += s2;
            ++count;
          }
        // Pixels are independent (each has its own random stream), so the
        // block mean's variance is the sum of theirs over count^2.
        const double se = std::sqrt(v) / count;
        const double z = opts.upper_only ? std::max(0.0, d / count) / se : std::fabs(d / count) / se;
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

// The candidate's variance at the case's settings over the reference's,
// each pixel channel's share capped at noise_cap times the reference's.
double noise_ratio(const Differences& D, const ScoreOptions& opts, double cap) {
  if (D.renders < 2) return -1;
  double num = 0, den = 0;
  for (int y = 0; y < D.h; ++y)
    for (int x = 0; x < D.w; ++x)
      for (int c = 0; c < D.nc; ++c) {
        const double vr = D.reference_var(x, y, c);
        num += std::min(D.candidate_case_var(x, y, c), cap * std::max(vr, opts.variance_floor));
        den += vr;
      }
  // A reference without noise to speak of (a point light at -s 4) has no
  // noise to compare with.
  return den > opts.variance_floor * D.w * D.h * D.nc * 1e-2 ? num / den : -1;
}

}  // namespace

double stopped_noise_ratio(const CandidateRenders& radiance, const ImageBuffer& ref_variance,
                           const ImageBuffer& ref_rate_mean, double cap) {
  const size_t k = radiance.images.size();
  if (k < 2) return -1;
  // Chosen by the reference's rate alone: choosing by the candidate's too
  // would pick the pixels where its renders happened to stop early, on a
  // lucky run of samples, and so were noisier than the same pixel's full
  // renders that the reference's variance mostly holds.
  std::vector<size_t> stopped;
  double total = 0;
  for (size_t i = 0; i < ref_variance.pixels.size(); ++i) {
    if (!(ref_rate_mean.pixels[i][0] < 1.0 - 1e-6)) continue;
    stopped.push_back(i);
    for (int c = 0; c < 3; ++c) total += ref_variance.pixels[i][c];
  }
  if (stopped.empty() || !(total > 0)) return -1;
  // A channel without noise in the reference (an emitter, a black
  // background) has no ratio to give; nor has one whose variance is float
  // rounding next to the others'.
  const double floor = 1e-6 * total / double(3 * stopped.size());
  double sum = 0;
  int counted = 0;
  for (size_t i : stopped)
    for (int c = 0; c < 3; ++c) {
      const double vr = ref_variance.pixels[i][c];
      if (!(vr > floor)) continue;
      double mean = 0, ss = 0;
      for (const ImageBuffer& img : radiance.images) mean += img.pixels[i][c];
      mean /= double(k);
      for (const ImageBuffer& img : radiance.images) ss += (img.pixels[i][c] - mean) * (img.pixels[i][c] - mean);
      sum += std::min(ss / double(k - 1) * radiance.share / vr, cap);
      ++counted;
    }
  return counted >= kStoppedNoiseMinChannels ? sum / counted : -1;
}

ImageBuffer mean_of(const std::vector<ImageBuffer>& images) {
  if (images.empty()) return ImageBuffer();
  ImageBuffer out(images[0].width, images[0].height);
  for (size_t i = 0; i < out.pixels.size(); ++i) {
    double sum[3] = {0, 0, 0};
    for (const ImageBuffer& img : images)
      for (int c = 0; c < 3; ++c) sum[c] += img.pixels[i][c];
    for (int c = 0; c < 3; ++c) out.pixels[i][c] = float(sum[c] / double(images.size()));
  }
  return out;
}

ImageScore score_image(const ImageBuffer& cand, const ImageBuffer& mean, const ImageBuffer& var, int runs,
                       const ScoreOptions& opts) {
  CandidateRenders one;
  one.images.push_back(cand);
  return score_renders(one, mean, var, runs, opts);
}

ImageScore score_renders(const CandidateRenders& cand, const ImageBuffer& mean, const ImageBuffer& var, int runs,
                         const ScoreOptions& opts) {
  if (cand.images.empty()) throw std::invalid_argument("score_renders: no candidate render");
  if (opts.deterministic) return score_by_value(cand.images[0], mean, opts);
  ImageScore s;
  const Differences D = differences(cand, mean, var, runs, opts);
  const int w = D.w, h = D.h, nc = D.nc;
  s.renders = D.renders;
  s.own_variance = D.renders > 1;

  // Per pixel channel, with the sums the image mean and relMSE need.
  s.channels_tested = w * h * nc;
  s.pixel_threshold = normal_two_sided_threshold(sidak_level(opts.alpha, s.channels_tested));
  s.pixel_z.assign(size_t(w) * h, 0.0f);
  double sum_m = 0, rel = 0, rel_expected = 0;
  double channel_d[3] = {0, 0, 0}, channel_v[3] = {0, 0, 0};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < nc; ++c) {
        const double d = D.d(x, y, c), s2 = D.sigma2(x, y, c), mv = value_from_top(mean, x, y, c);
        channel_d[c] += d;
        channel_v[c] += s2;
        const double z = std::max(0.0, (opts.upper_only ? d : std::fabs(d)) - opts.pixel_slack) / std::sqrt(s2);
        if (z > s.pixel_threshold) ++s.channels_failed;
        float& pz = s.pixel_z[size_t(y) * w + x];
        pz = std::max(pz, float(z));
        sum_m += mv;
        const double denom = mv * mv + 0.01;
        rel += d * d / denom;
        rel_expected += D.expected(x, y, c) / denom;
      }
  const double n = double(s.channels_tested);
  s.mean_reference = sum_m / n;
  s.mean_candidate = (sum_m + channel_d[0] + channel_d[1] + channel_d[2]) / n;
  s.relmse = rel / n;
  s.relmse_expected = rel_expected / n;
  s.noise_ratio = noise_ratio(D, opts, opts.noise_cap);
  s.tail_ratio = noise_ratio(D, opts, HUGE_VAL);
  const bool pixels_ok = s.channels_failed <= (1.0 - opts.min_pass_fraction) * n;
  s.pixels_off = !pixels_ok;

  if (opts.mean_test) image_mean_test(channel_d, channel_v, nc, opts, &s);
  const bool blocks_ok = !opts.block_test || block_test(D, opts, &s);
  s.blocks_off = !blocks_ok;
  s.passed = pixels_ok && blocks_ok && !s.mean_failed;
  return s;
}

double ImageScore::max_mean_z() const {
  double z = 0;
  for (double v : mean_z) z = std::max(z, std::fabs(v));
  return z;
}

std::string ImageScore::summary() const {
  char buf[240];  // each piece is short
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
  // relMSE is relative to m^2 + 0.01: where the image holds fireflies (a
  // near-mirror metal seeing the light) it is large for any render, the
  // reference's too; what matters is how it compares with the noise.
  std::snprintf(buf, sizeof buf, ", relMSE %.3g (noise alone %.3g)", relmse, relmse_expected);
  s += buf;
  if (noise_ratio >= 0) {
    std::snprintf(buf, sizeof buf, ", variance %.2fx the reference's%s", noise_ratio,
                  noise_ratio < 1.0 ? " (less is fine)" : "");
    s += buf;
  }
  if (renders > 1) s += ", " + std::to_string(renders) + " renders";
  return s;
}

}  // namespace grader
