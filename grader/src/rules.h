// The grader's rules beyond each case's line: how many renders judge a
// Monte Carlo image, the false-failure budget of a whole grading run and
// how it is shared among the images, the noise bound, and what costs are
// compared with.
#pragma once
#include <map>
#include <string>
#include <vector>

#include "grader/src/case_list.h"
#include "grader/src/checks.h"
#include "grader/src/reference.h"
#include "grader/src/scoring.h"

namespace grader {

struct Rules {
  // A Monte Carlo case is rendered this many times at different seeds,
  // and judged with the spread of those renders (scoring.h). Where the
  // case's -s divides into renders of 2 samples or more, each render takes
  // its share of -s, so that the whole costs one render of the case.
  int renders = 4;
  // The chance that a correct build loses points anywhere in a whole
  // grading run, shared equally among the Monte Carlo images the case list
  // scores (each case's image, and the sample-rate image of part 5's).
  double run_alpha = 1e-3;
  int scored_images = 1;
  // Noise: a candidate more than this many times the reference's variance
  // keeps this share of the case's points (the image is right; the method
  // is not the one the case asks for).
  double noise_bound = 4.0;
  double noise_credit = 0.5;
  // Heavy tails: a candidate whose variance with nothing capped (every
  // firefly counted in full) is more than this many times the reference's
  // keeps nothing. Orders of magnitude above what correct estimators reach
  // (instructors/legal_variants/variants.md; the reference with -H where
  // light sampling is asked), orders of magnitude below what a wrong weight
  // that makes a few samples enormous gives (mf_D_tan2_inverted: 10^12).
  double tail_bound = 1000.0;
  // Part 5: where pixels stop before -s, a correct rule leaves about the
  // reference's noise whatever the estimator (scoring.h's
  // stopped_noise_ratio); more than this many times it stops too early.
  // Each pixel channel's ratio counts up to stopped_noise_cap: a correct
  // build's one pixel that a rare path lights in one render (p5_sky) must
  // not move the mean of a few hundred channels; a rule that stops too
  // early is noisier everywhere (2 to 8 times), far below the cap.
  double stopped_noise_bound = 1.5;
  double stopped_noise_cap = 10.0;
  // Cases that keep only the paths of exactly -m bounces (-o 0) let the
  // legal choices' extra noise compound at every bounce (roulette at 0.5
  // rather than 0.7 costs 1.4 times the variance per bounce, uniform bounce
  // directions 4/3 on a diffuse surface): their bound grows by this factor
  // per bounce after the first.
  double noise_growth_per_bounce = 1.5;
  // The bound for case c: noise_bound, or more for -o 0 at -m >= 2.
  double noise_bound_for(const Case& c) const;
  CostBounds costs;
  // A plain binary BVH's costs per case (reference_images/plain_bvh_costs.json).
  std::map<std::string, QueryCosts> plain_bvh;

  // Each scored image's share of run_alpha, split between its block and
  // image-mean tests.
  double image_alpha() const { return run_alpha / std::max(1, scored_images); }
};

// The rules for grading with the case list `all` (every case of the file,
// whatever a run selects, so that a case's verdict does not depend on
// which others are graded beside it) and the references in `references`.
// A case without a usable reference counts as a scored Monte Carlo image.
Rules make_rules(const std::vector<Case>& all, const std::string& references);
// The same with hidden cases besides, whose references (and plain BVH
// costs) are in `hidden_references`.
Rules make_rules(const std::vector<Case>& all, const std::string& references, const std::vector<Case>& hidden,
                 const std::string& hidden_references);

// Reads a plain BVH's costs per case: {"cases": {"name": {"closest_tests_per_query": x,
// "shadow_tests_per_query": y}, ...}}. Missing file: no entries.
// Throws std::runtime_error naming the file when it is malformed.
std::map<std::string, QueryCosts> read_plain_bvh_costs(const std::string& path);

// What a case asks for, in the student's words, for the noise check's
// message: "light sampling (-l 4)", "uniform hemisphere sampling (-H)".
std::string case_method(const Case& c);

// The candidate's renders of a case: the case as each render runs it (with
// its share of -s), how many, and each render's share of the samples.
// Renders from part 5 on share -s only when it is at most one batch of
// adaptive sampling (-a B, by default the renderer's 32): otherwise each
// takes the whole -s, as the reference's renders did.
constexpr int kDefaultAdaptiveBatch = 32;  // stages/part5_adaptive_sampling: AdaptiveOptions::batch
struct RenderPlan {
  Case c;
  int renders = 1;
  double share = 1.0;
};
RenderPlan render_plan(const Case& c, bool deterministic, const Rules& rules);

// The seed of the candidate's render k of a case graded at `seed`:
// 2^32 + 64 seed + k, never one of the references' (10^6 + i).
uint64_t candidate_seed(uint64_t seed, int k);

}  // namespace grader
