// Statistical scoring of a candidate image against a reference.
//
// The reference of a case is B independent renders of the reference build
// at exactly the case's settings (different seeds): their per-pixel mean m
// and per-pixel variance v_r (the variance of ONE render at the case's
// budget, estimated across the B renders).
//
// The candidate is K independent renders of the graded build (K >= 2 for a
// Monte Carlo case), and it is judged with ITS OWN noise, never the
// reference's: a correct estimator that is noisier than the reference's (a
// roulette probability of 0.5, uniform bounces, ...) has the same expected
// image, and that is the question each test asks. From the K renders: their
// mean c and u = s^2 / K, the variance of c estimated from the renders'
// spread s^2. The difference c - m then has variance u + v_r / B.
//
// Variances estimated from a few renders are noisy and, where rare paths
// never showed, too small. Each pixel channel's u and v_r are therefore
// taken as at least the mean over its 3x3 neighbourhood (neighbouring
// pixels see nearly the same paths): pooling gives u about 9 (K - 1)
// degrees of freedom, and taking the larger of a pixel's own value and
// the pooled one is conservative at edges, where the variance jumps.
//
// Three tests, in the manner of Mitsuba 3's render tests:
//  - per pixel channel: z = (|c - m| - slack) / sqrt(max(u + v_r / B,
//    floor)); the image passes when at least `min_pass_fraction` of the
//    channels pass (a few pixels may sit on an edge or meet a firefly the
//    renders' spread did not show);
//  - per 8x8 block and channel (Monte Carlo cases only): the mean of
//    c - m over the block, each pixel's difference winsorised at +-3 of its
//    standard deviations so that a lone firefly cannot decide it, against
//    its standard error. A small bias that hides in per-pixel noise (a
//    missing Russian-roulette division) shows in 64-pixel averages; the
//    image fails when two or more distinct blocks fail (one block alone is
//    a lone outlier's doing, as calibration showed).
//  - per channel, the image mean (Monte Carlo cases only): the mean of c - m
//    over the whole image against its standard error. A bias spread thinly
//    over the image (a 14 % darker render whose pixels are too noisy for
//    any 8x8 block to show it) is tens of standard errors away here.
// Noise is judged apart: `noise_ratio` is the candidate's variance at the
// case's settings over the reference's (each pixel's share capped, so
// that one firefly cannot decide it); the checks (checks.h) hold it to a
// generous bound where the case asks for a method whose noise matters.
// `tail_ratio` is the same ratio uncapped, where heavy tails count: judged
// by its own noise, a build whose error is a few enormous pixels always
// looks like noise (its spread is as enormous as its error), so the
// checks also hold the uncapped ratio to a bound orders of magnitude above
// what any correct estimator's fireflies reach.
//
// With a single candidate render (K = 1: `grader compare` of one file, the
// viewer's difference overlay) there is no spread to estimate u from, and
// the reference's variance stands in for it (u = v_r): the old, stricter
// question "is this render a draw of the reference's estimator?".
//
// A deterministic reference (every reference render gave the same image:
// normal shading at one sample per pixel) is compared by value instead:
// each channel must lie within abs_tolerance + rel_tolerance |m| of it, as
// floating-point round-off does, so a systematic error of a few percent
// fails (the per-pixel z test's variance floor would let 0.05 through).
// relMSE = mean (c - m)^2 / (m^2 + 0.01) is reported beside it, with the
// value noise alone would give, for partial credit and for people.
#pragma once
#include <string>
#include <vector>

#include "common/image.h"

namespace grader {

// Images are the renderer's ImageBuffer (pixel (0, 0) at the bottom left,
// three channels). The statistics walk them as they are seen, rows from the
// top: the 8x8 blocks start at the top-left corner, and per-pixel results
// (pixel_z) and positions in messages count rows from the top, as the
// pictures (pictures.h) do.
using pt::ImageBuffer;

struct ScoreOptions {
  int channels = 3;                  // colour channels scored: 1 for a sample-rate image (the rate is in each)
  double alpha = 0.01;               // the per-pixel test's family-wise level (Sidak over the channels)
  double min_pass_fraction = 0.9975; // of pixel channels
  double variance_floor = 1e-4;      // on the variance of c - m
  // Per-pixel test only: |c - m| less this much is what is divided by
  // sigma. A sample-rate image moves in steps of one batch, and a pixel that
  // takes one batch more than it did in every one of the B reference renders
  // is a rare event of a correct renderer, not evidence (where many pixels
  // are such, as in an open scene of smooth light, dozens of them per image
  // would fail the test: calibration measured half the renders of one case).
  // Blocks and the image mean still see a systematic shift of any size.
  double pixel_slack = 0.0;
  // Only a candidate above the reference fails (per pixel, block and the
  // image mean): the sample-rate image of a build whose estimator is less
  // noisy than the reference's may lie below it (its own noise says whether
  // it stopped too early: stopped_noise_ratio).
  bool upper_only = false;
  bool block_test = true;            // off for deterministic references
  int block_size = 8;
  double block_clamp = 3.0;          // pixel differences winsorised at +-3 sigma
  int min_blocks_to_fail = 2;        // distinct blocks (any channel) that fail the image
  // The chance that a correct render fails the block test: each block's
  // level is set so that min_blocks_to_fail or more distinct blocks fail
  // with at most this probability.
  double block_alpha = 1e-3;
  bool mean_test = true;             // off for deterministic references
  // The image-mean test's family-wise level (Sidak over the channels). The
  // grader sets it, with block_alpha, from its false-failure budget for a
  // whole grading run (grade.h): one correct build in a thousand may lose a
  // point somewhere to chance, not one case in a thousand.
  double mean_alpha = 1e-3;
  // The noise ratio counts each pixel channel's variance up to this many
  // times the reference's: a lone firefly of a correct estimator must not
  // make it look noisy everywhere.
  double noise_cap = 50.0;
  bool deterministic = false;        // compare by value (tolerances below), no z tests
  double abs_tolerance = 1e-3;       // deterministic: |c - m| <= abs + rel |m|
  double rel_tolerance = 1e-3;
};

struct ImageScore {
  bool passed = false;
  int renders = 1;                  // candidate renders scored
  bool own_variance = false;        // judged with the candidate's own spread (renders >= 2)
  int channels_tested = 0, channels_failed = 0;
  int blocks_tested = 0, blocks_failed = 0;  // (block, channel) pairs
  int distinct_blocks_failed = 0;
  bool pixels_off = false, blocks_off = false;  // which tests failed the image (and mean_failed)
  double pixel_threshold = 0, block_threshold = 0;  // |z| limits
  double max_block_z = 0;
  bool deterministic = false;       // compared by value: pixel_threshold is unused
  double max_abs_difference = 0;    // deterministic: the largest |c - m|
  // The image-mean test, per channel (Monte Carlo cases).
  bool mean_tested = false, mean_failed = false;
  double mean_z[3] = {0, 0, 0};
  double mean_threshold = 0;
  double relmse = 0, relmse_expected = 0;
  double mean_candidate = 0, mean_reference = 0;
  // The candidate's variance at the case's settings over the reference's
  // (-1: not measured: one render, or a reference without noise).
  double noise_ratio = -1;
  // The same ratio with nothing capped (-1: not measured): every pixel
  // channel counts in full, so a few astronomically bright pixels (a
  // firefly a thousand times anything the reference's estimator makes)
  // show here, where noise_ratio's cap hides them. A correct estimator's
  // rare fireflies move it by a few times; a wrong weight that makes a
  // handful of samples enormous moves it by orders of magnitude.
  double tail_ratio = -1;
  std::vector<float> pixel_z;  // per pixel, the largest |z| over channels (deterministic: |c - m| / tolerance)
  double max_mean_z() const;   // the largest |z| of the image-mean test
  // "99.98% px ok, 0/192 blocks off, mean |z| 0.8, relMSE 0.012 (noise alone 0.011)", or
  // for a deterministic image "100.00% px within 0.001, largest difference 2e-07". A figure
  // that alone would look like a failure in a passing image says why it is not: a relMSE
  // far above 1 is set beside what the renders' own noise gives, a variance below the
  // reference's says "less is fine".
  std::string summary() const;
};

// The graded build's renders of one case: independent renders at
// different seeds. `share` is each render's share of the case's samples:
// 1 / K when the case's -s was split over the K renders, 1 when every
// render took the case's -s; the variance of one render at the case's
// settings is then share times the renders' spread.
struct CandidateRenders {
  std::vector<ImageBuffer> images;
  double share = 1.0;
};

// The sizes must agree (checked by the caller); values must be finite.
// With two or more renders the candidate is judged with its own variance;
// with one, with the reference's.
ImageScore score_renders(const CandidateRenders& candidate, const ImageBuffer& mean, const ImageBuffer& variance,
                         int reference_runs, const ScoreOptions& opts);
// One render (judged with the reference's variance).
ImageScore score_image(const ImageBuffer& candidate, const ImageBuffer& mean, const ImageBuffer& variance,
                       int reference_runs, const ScoreOptions& opts);

// Adaptive sampling's rule, 1.96 sigma / sqrt(n) <= T mu, stops a pixel
// when its own noise reaches a level set by the tolerance, whatever the
// estimator: a less noisy estimator gets there with fewer samples. So
// where pixels stop early, a correct rule leaves about the reference's
// noise in the image (less where a pixel stops at its first batch), and a
// rule that stops too early leaves more. This is the mean, over the pixel
// channels where the reference's renders stopped before -s (its mean rate
// below 1) and have noise, of the candidate's variance of one render over
// the reference's, each capped at `cap`: every pixel counts the same, so a
// few pixels of enormous variance (the edge of a light seen directly,
// whose 4-render variance is itself very noisy) cannot make a correct
// build look noisy or a wrong one quiet. -1 when fewer than
// kStoppedNoiseMinChannels channels qualify. `radiance`: the candidate's
// renders (each with the whole -s); `ref_rate_mean`: the reference's rate.
constexpr int kStoppedNoiseMinChannels = 30;
double stopped_noise_ratio(const CandidateRenders& radiance, const ImageBuffer& ref_variance,
                           const ImageBuffer& ref_rate_mean, double cap);

// The mean of several renders, pixel by pixel (the candidate's image).
ImageBuffer mean_of(const std::vector<ImageBuffer>& images);

// The two-sided standard-normal threshold z with P(|Z| > z) = p.
double normal_two_sided_threshold(double p);
// Šidák: the per-test level giving family-wise level alpha over n tests.
double sidak_level(double alpha, int n);
// The level per test at which `at_least` or more of n independent tests
// fail with probability at most alpha (a bound: C(n, k) p^k <= alpha).
double level_for_at_least(double alpha, int n, int at_least);

// The value of channel `c` at column x of row `row` counted from the top.
inline float value_from_top(const ImageBuffer& img, int x, int row, int c) { return img.at(x, img.height - 1 - row)[c]; }

// Counts pixels with a non-finite channel; `first_x`, `first_y` get the
// first one's position (rows from the top).
int count_non_finite(const ImageBuffer& img, int* first_x, int* first_y);

}  // namespace grader
