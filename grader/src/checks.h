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

// Bounds of the cost checks, relative to the reference's recorded figures.
// From part 2 on every case checks them: a BVH that is correct but tests
// too much (for camera and bounce rays, or only for shadow rays) loses the
// case's points. The slack covers scenes where the reference needs almost
// no tests (shadow rays under an open sky).
struct CostBounds {
  double tests_factor = 8.0;     // tests per query <= 8x the reference's + slack, for each kind of query
  double tests_slack = 4.0;     // a leaf of 4 primitives where the reference enters none
  double shadow_factor = 1.5;    // shadow rays per closest-hit query <= 1.5x the reference's
  double min_speedup = 10.0;     // speedup: part 1 tests per ray / part 2's
};

// What one check found.
struct Check {
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
Check check_rate_image(const ImageScore& rate, double points);

// Per kind of query, from a render's --stats-json: primitive tests per
// closest-hit query and per shadow query, shadow queries per closest-hit
// query (-1: not measured).
struct QueryCosts {
  double closest_tests = -1, shadow_tests = -1, shadow_per_query = -1;
};

// The costs, against the reference's (its -1s are not checked). `stats`:
// the render's --stats-json, or nullptr when it wrote none. Any problem
// leaves no credit. `measured` gets the render's figures.
Check check_costs(const Json* stats, const QueryCosts& reference, const CostBounds& bounds, double points,
                  QueryCosts* measured);

// The speed-up of the BVH: the intersection tests per ray it saves over the
// --part 1 render `part1` decide; the time speed-up is reported. Any
// problem leaves no credit. `render_seconds` and `tests_per_ray` are the
// BVH render's (-1: not reported); `part1_seconds` and `speedup` get the
// figures (-1: not measured).
Check check_speedup(const RenderOutput& part1, double render_seconds, double tests_per_ray, const CostBounds& bounds,
                    double points, double* part1_seconds, double* speedup);

}  // namespace grader
