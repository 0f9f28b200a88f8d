// The checks a case is graded by, one per kind, each on figures already
// measured (so that each can be tested alone): the image against the
// reference, the sample-rate image, the costs per query (from part 2 on)
// and the BVH's speed-up. Each returns its problems and the most credit it
// leaves; grade_case (grade.h) renders, runs the checks that apply and
// keeps the smallest credit.
#pragma once
#include <string>
#include <vector>

#include "common/json.h"
#include "grader/src/run_case.h"
#include "grader/src/scoring.h"

namespace grader {

// Bounds of the cost checks. Cost is judged where the course teaches it:
// part 2's cases hold the build's BVH to what a plain binary BVH built the
// way the course suggests (midpoint split, leaves of at most 4, a
// closest-hit and an any-hit query) needs on the same case, with room for
// the course's other legal choices (median splits, leaves of 1 to 8, a
// pointer tree, no near-child-first order); parts 3-5 fail on cost only
// for a pathological build (no BVH at all, or a query that visits
// everything), never for an order of tests that leaves the image as it is.
struct CostBounds {
  double part2_factor = 3.0;          // part 2: tests per query <= 3x the plain BVH's + slack
  double pathological_factor = 20.0;  // parts 3-5: tests per query <= 20x the plain BVH's + slack
  double tests_slack = 4.0;           // a leaf of 4 primitives where the plain BVH enters none
  // Shadow rays per closest-hit query <= 3x the reference's: a delta light
  // sampled -l times (8x at -l 8) fails, while testing cos theta after the
  // shadow ray instead of before (about 2x) passes.
  double shadow_factor = 3.0;
  double min_speedup = 10.0;          // speedup: part 1 tests per ray / part 2's
};

// What one check found.
struct Check {
  std::string name;                   // "image", "noise", "rate", "cost", "speedup": the signature's failed_<name>
  std::vector<std::string> problems;  // empty: passed
  double credit = 0;                  // the most the case may earn after it (all its points when passed)
  std::string metric;                 // added to the case's statistics line
};

// Partial credit for an image that fails the test: half the points when
// its relMSE is at the noise level, falling linearly to none at 0.05 above
// it, and none at all when its mean radiance is off by more than 10 %.
double partial_credit(const ImageScore& s, double points);

// The image, scored against the reference: partial credit when it fails.
// metric: the score's summary.
Check check_image(const ImageScore& image, double points);

// The sample-rate image (adaptive cases): partial credit when it fails.
// `expected` says what the rate was compared with ("the reference's", or
// what the build's own noise implies), for the message.
Check check_rate_image(const ImageScore& rate, double points, const std::string& expected);

// Adaptive sampling judged by the build's own noise: `stopped_ratio` is
// stopped_noise_ratio (scoring.h), the build's variance where its pixels
// stop before -s over the reference's there. Beyond `bound` the rule stops
// too early for the noise it leaves (a rule that checks after every sample,
// or tests sigma^2 for sigma), and the case keeps `credit_share` of its
// points. -1: not measured.
Check check_stopped_noise(double stopped_ratio, double bound, double credit_share, double points);

// Per kind of query, from a render's --stats-json: primitive tests per
// closest-hit query and per shadow query, shadow queries per closest-hit
// query (-1: not measured).
struct QueryCosts {
  double closest_tests = -1, shadow_tests = -1, shadow_per_query = -1;
};

// What a case's costs are compared with: a plain binary BVH's tests per
// query on the case (reference_images/plain_bvh_costs.json; its
// shadow_per_query is unused), or where that has no figure for the case,
// the reference's own (`plain` false); and the reference's shadow rays per
// closest-hit query. -1: not known, not checked.
struct CostBaseline {
  QueryCosts tests;
  bool plain = true;
  double reference_shadow_per_query = -1;
};

// The costs of a case of part `part`. `stats`: the render's --stats-json
// (counts summed over the case's renders), or nullptr when it wrote none.
// Any problem leaves no credit. `measured` gets the render's figures.
Check check_costs(const Json* stats, int part, const CostBaseline& baseline, const CostBounds& bounds, double points,
                  QueryCosts* measured);

// Noise, judged apart from the image: a candidate whose variance at the
// case's settings is more than `bound` times the reference's (the method
// the case asks for) fails this check alone and keeps `credit_share` of
// the points. `method`: what the case asks for, in the student's words
// ("light sampling (no -H)"). A candidate whose uncapped variance (its
// fireflies counted in full, ImageScore::tail_ratio) is more than
// `tail_bound` times the reference's is not noisier-but-right: a few of
// its samples are orders of magnitude too bright, and it keeps nothing.
Check check_noise(const ImageScore& image, double bound, double tail_bound, double credit_share,
                  const std::string& method, double points);

// The speed-up of the BVH: the intersection tests per ray it saves over the
// --part 1 render `part1` decide; the time speed-up is reported. Any
// problem leaves no credit. `render_seconds` and `tests_per_ray` are the
// BVH render's (-1: not reported); `part1_seconds` and `speedup` get the
// figures (-1: not measured).
Check check_speedup(const RenderOutput& part1, double render_seconds, double tests_per_ray, const CostBounds& bounds,
                    double points, double* part1_seconds, double* speedup);

}  // namespace grader
