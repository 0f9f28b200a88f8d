// Statistical scoring of a candidate image against a reference.
//
// The reference of a case is B independent renders of the reference build
// at exactly the case's settings (different seeds): their per-pixel mean m
// and per-pixel variance v (the variance of ONE render at the case's
// budget, estimated across the B renders). A correct candidate render c is
// then another independent draw, so c - m has variance v (1 + 1/B).
//
// Two tests, both at a family-wise level alpha with a Šidák-corrected
// per-test threshold, in the manner of Mitsuba 3's render tests:
//  - per pixel channel: z = |c - m| / sqrt(max(v* (1 + 1/B), floor)), where
//    v* = max(v, mean of v over the 3x3 neighbourhood) guards against
//    variances that B renders underestimate; the image passes when at least
//    `min_pass_fraction` of the channels pass (a few pixels may sit on an
//    edge or catch a firefly);
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
  double alpha = 0.01;               // family-wise, per test kind
  double min_pass_fraction = 0.9975; // of pixel channels
  double variance_floor = 1e-4;      // on v (1 + 1/B)
  // Per-pixel test only: |c - m| less this much is what is divided by
  // sigma. A sample-rate image moves in steps of one batch, and a pixel that
  // takes one batch more than it did in every one of the B reference renders
  // is a rare event of a correct renderer, not evidence (where many pixels
  // are such, as in an open scene of smooth light, dozens of them per image
  // would fail the test: calibration measured half the renders of one case).
  // Blocks and the image mean still see a systematic shift of any size.
  double pixel_slack = 0.0;
  bool block_test = true;            // off for deterministic references
  int block_size = 8;
  double block_clamp = 3.0;          // pixel differences winsorised at +-3 sigma
  int min_blocks_to_fail = 2;        // distinct blocks (any channel) that fail the image
  bool mean_test = true;             // off for deterministic references
  // The image-mean test's family-wise level. Lower than alpha: its power is
  // to spare (a 14 % bias is tens of standard errors), and at 0.01 it alone
  // would fail one correct render in a hundred per case, a false failure
  // for every fourth student over the Monte Carlo cases.
  double mean_alpha = 0.001;
  bool deterministic = false;        // compare by value (tolerances below), no z tests
  double abs_tolerance = 1e-3;       // deterministic: |c - m| <= abs + rel |m|
  double rel_tolerance = 1e-3;
};

struct ImageScore {
  bool passed = false;
  int channels_tested = 0, channels_failed = 0;
  int blocks_tested = 0, blocks_failed = 0;  // (block, channel) pairs
  int distinct_blocks_failed = 0;
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
  std::vector<float> pixel_z;  // per pixel, the largest |z| over channels (deterministic: |c - m| / tolerance)
  double max_mean_z() const;   // the largest |z| of the image-mean test
  // "99.98% px ok, 0/192 blocks off, mean |z| 0.8, relMSE 0.012 (noise 0.011)", or for a
  // deterministic image "100.00% px within 0.001, largest difference 2e-07"
  std::string summary() const;
};

// The sizes must agree (checked by the caller); values must be finite.
ImageScore score_image(const ImageBuffer& candidate, const ImageBuffer& mean, const ImageBuffer& variance,
                       int reference_runs, const ScoreOptions& opts);

// The two-sided standard-normal threshold z with P(|Z| > z) = p.
double normal_two_sided_threshold(double p);
// Šidák: the per-test level giving family-wise level alpha over n tests.
double sidak_level(double alpha, int n);

// The value of channel `c` at column x of row `row` counted from the top.
inline float value_from_top(const ImageBuffer& img, int x, int row, int c) { return img.at(x, img.height - 1 - row)[c]; }

// Counts pixels with a non-finite channel; `first_x`, `first_y` get the
// first one's position (rows from the top).
int count_non_finite(const ImageBuffer& img, int* first_x, int* first_y);

}  // namespace grader
