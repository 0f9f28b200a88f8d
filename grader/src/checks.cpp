#include "grader/src/checks.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "grader/src/text.h"

namespace grader {

double partial_credit(const ImageScore& s, double points) {
  // A black image of a dim scene has a small relMSE, yet is simply wrong.
  if (std::fabs(s.mean_candidate - s.mean_reference) > 0.1 * std::fabs(s.mean_reference)) return 0.0;
  const double excess = std::max(0.0, s.relmse - s.relmse_expected);
  return 0.5 * points * std::clamp(1.0 - excess / 0.05, 0.0, 1.0);
}

namespace {

// "image differs from the reference: ...", what failed and by how much:
// the figures of the tests that failed first, then the others'.
std::string image_problem(const ImageScore& img) {
  char buf[400];
  if (img.deterministic) {
    std::snprintf(buf, sizeof buf,
                  "image differs from the reference: %d of %d pixel channels off by more than round-off (largest "
                  "difference %.3g); mean radiance %.4g vs %.4g",
                  img.channels_failed, img.channels_tested, img.max_abs_difference, img.mean_candidate,
                  img.mean_reference);
    return buf;
  }
  std::vector<std::string> failed, passed;
  const auto add = [&](bool off, const std::string& text) { (off ? failed : passed).push_back(text); };
  if (img.mean_tested)
    add(img.mean_failed, fmt("image mean |z| = %.1f", img.max_mean_z()) + fmt(" (limit %.2f)", img.mean_threshold));
  if (img.blocks_tested > 0)
    add(img.blocks_off, std::to_string(img.blocks_failed) + " of " + std::to_string(img.blocks_tested) +
                            " blocks beyond " + fmt("|z| = %.2f", img.block_threshold));
  add(img.pixels_off, std::to_string(img.channels_failed) + " of " + std::to_string(img.channels_tested) +
                          " pixel channels beyond " + fmt("|z| = %.2f", img.pixel_threshold));
  std::string parts;
  for (const std::string& p : failed) parts += (parts.empty() ? "" : ", ") + p;
  if (!passed.empty()) {
    parts += parts.empty() ? "" : " (within limits: ";
    for (size_t i = 0; i < passed.size(); ++i) parts += (i ? ", " : "") + passed[i];
    parts += failed.empty() ? "" : ")";
  }
  std::snprintf(buf, sizeof buf, "image differs from the reference: %s; mean radiance %.4g vs %.4g", parts.c_str(),
                img.mean_candidate, img.mean_reference);
  return buf;
}

}  // namespace

Check check_image(const ImageScore& image, double points) {
  Check k;
  k.name = "image";
  k.metric = image.summary();
  k.credit = points;
  if (!image.passed) {
    k.problems.push_back(image_problem(image));
    k.credit = partial_credit(image, points);
  }
  return k;
}

Check check_rate_image(const ImageScore& rate, double points, const std::string& expected) {
  Check k;
  k.name = "rate";
  k.metric = "; rate: " + rate.summary();
  k.credit = points;
  if (!rate.passed) {
    // The mean rate first (what a student can act on), then the figures
    // of the tests that failed, then the others'.
    std::vector<std::string> failed, passed;
    const auto add = [&](bool off, const std::string& text) { (off ? failed : passed).push_back(text); };
    add(rate.mean_failed, fmt("mean |z| = %.1f", rate.max_mean_z()));
    add(rate.blocks_off, std::to_string(rate.blocks_failed) + " of " + std::to_string(rate.blocks_tested) +
                             " blocks off");
    add(rate.pixels_off, std::to_string(rate.channels_failed) + " of " + std::to_string(rate.channels_tested) +
                             " pixels beyond " + fmt("|z| = %.2f", rate.pixel_threshold));
    std::string figures;
    for (const std::string& f : failed) figures += (figures.empty() ? "" : ", ") + f;
    for (size_t i = 0; i < passed.size(); ++i)
      figures += std::string(i == 0 ? (failed.empty() ? "" : " (within limits: ") : ", ") + passed[i];
    if (!failed.empty() && !passed.empty()) figures += ")";
    k.problems.push_back(fmt("sample-rate image differs: mean rate %.3f vs ", rate.mean_candidate) +
                         fmt("%.3f", rate.mean_reference) + (expected.empty() ? "" : " (" + expected + ")") +
                         "; " + figures);
    k.credit = partial_credit(rate, points);
  }
  return k;
}

Check check_stopped_noise(double stopped_ratio, double bound, double credit_share, double points) {
  Check k;
  k.name = "rate";
  k.credit = points;
  if (stopped_ratio < 0) return k;
  k.metric = fmt("; where pixels stop early, variance %.2fx the reference's (mean per pixel)", stopped_ratio);
  if (stopped_ratio <= bound) return k;
  k.problems.push_back(fmt("pixels stop too early: where they stop before -s, the image's variance per pixel is %.2fx ",
                           stopped_ratio) +
                       fmt("the reference's (at most %.1fx: the rule 1.96 sigma / sqrt(n) <= T mu leaves about the ", bound) +
                       "reference's noise, whatever the estimator; is it tested once per batch, with sigma, not sigma^2?)");
  k.credit = credit_share * points;
  return k;
}

Check check_costs(const Json* stats, int part, const CostBaseline& baseline, const CostBounds& bounds, double points,
                  QueryCosts* measured) {
  Check k;
  k.name = "cost";
  if (!stats || stats->num("closest_queries", 0) <= 0) {
    k.problems.push_back("no ray counts (--stats-json stats.json)");
    return k;
  }
  const double closest_queries = stats->num("closest_queries", 0), shadow_queries = stats->num("shadow_queries", 0);
  const double tests = stats->num("primitive_tests", 0), shadow = stats->num("shadow_primitive_tests", 0);
  const double closest_tests = (tests - shadow) / closest_queries;
  const double shadow_tests = shadow_queries > 0 ? shadow / shadow_queries : 0;
  const double shadow_per_query = shadow_queries / closest_queries;
  measured->closest_tests = closest_tests;
  if (shadow_queries > 0) measured->shadow_tests = shadow_tests;
  measured->shadow_per_query = shadow_per_query;

  // Part 2 is where the BVH is taught and graded; later parts only catch
  // a BVH that is not there.
  const bool taught = part == 2;
  const double factor = taught ? bounds.part2_factor : bounds.pathological_factor;
  const auto limit = [&](double base) { return factor * base + bounds.tests_slack; };
  const QueryCosts& base = baseline.tests;
  const std::string whose = baseline.plain ? "what a plain binary BVH needs here" : "the reference's";
  const std::string label = baseline.plain ? "plain BVH" : "ref";
  if (tests <= 0)
    k.problems.push_back("no intersection tests counted: every primitive test counts into thread_ray_stats() "
                         "(see the part 2 contract)");
  if (base.closest_tests >= 0 && closest_tests > limit(base.closest_tests))
    k.problems.push_back(
        fmt("%.1f intersection tests per camera or bounce ray, ", closest_tests) +
        fmt("more than %.0fx ", factor) + whose + fmt(" (%.2f)", base.closest_tests) +
        (taught ? ": the BVH does not cull enough (are leaves small, and are boxes the ray misses skipped?)"
                : ": the closest-hit query is not using the BVH"));
  if (base.shadow_tests >= 0 && shadow_queries > 0 && shadow_tests > limit(base.shadow_tests))
    k.problems.push_back(fmt("%.1f intersection tests per shadow ray, ", shadow_tests) + fmt("more than %.0fx ", factor) +
                         whose +
                         fmt(" (%.2f): the occlusion query does not use the BVH (every primitive tested?)",
                             base.shadow_tests));
  if (baseline.reference_shadow_per_query > 0 &&
      shadow_per_query > bounds.shadow_factor * baseline.reference_shadow_per_query)
    k.problems.push_back(fmt("%.2f shadow rays per closest-hit query, ", shadow_per_query) +
                         fmt("%.1fx the reference's ", shadow_per_query / baseline.reference_shadow_per_query) +
                         fmt("%.2f: a point or directional light needs one sample, not -l", baseline.reference_shadow_per_query));
  k.metric = fmt("; tests per query %.2f", closest_tests) + " (" + label + fmt(" %.2f)", base.closest_tests);
  if (shadow_queries > 0)
    k.metric += fmt(", per shadow ray %.2f", shadow_tests) + " (" + label + fmt(" %.2f)", base.shadow_tests) +
                fmt("; %.2f shadow rays per query", shadow_per_query) +
                fmt(" (ref %.2f)", baseline.reference_shadow_per_query);
  k.credit = k.problems.empty() ? points : 0;
  return k;
}

Check check_noise(const ImageScore& image, double bound, double tail_bound, double credit_share,
                  const std::string& method, double points) {
  Check k;
  k.name = "noise";
  k.credit = points;
  if (image.tail_ratio > tail_bound) {
    // Judged by its own noise such a build always looks like noise (its
    // spread is as enormous as its error); the capped ratio cannot see it.
    k.problems.push_back(fmt("fireflies: with its brightest pixels counted in full, the image's variance is %.3gx ",
                             image.tail_ratio) +
                         "that of " + method +
                         fmt(" (a correct estimator's stays below %.0fx): a few samples are orders of magnitude too "
                             "bright (can some weight grow without bound: a division by a number that can be nearly "
                             "0, an exponent upside down?)",
                             tail_bound));
    k.credit = 0;
    return k;
  }
  if (image.noise_ratio < 0 || image.noise_ratio <= bound) return k;
  k.problems.push_back(fmt("the image is right but too noisy: its variance is %.1fx ", image.noise_ratio) +
                       "that of " + method + fmt(" at the same settings (at most %.0fx allowed)", bound));
  k.credit = credit_share * points;
  return k;
}

Check check_speedup(const RenderOutput& part1, double render_seconds, double tests_per_ray, const CostBounds& bounds,
                    double points, double* part1_seconds, double* speedup) {
  Check k;
  k.name = "speedup";
  *part1_seconds = part1.ok && part1.has_stats ? part1.stats.num("render_seconds", -1) : -1;
  if (!part1.ok) {
    k.problems.push_back("the --part 1 (no BVH) render failed: " + part1.failure);
    return k;
  }
  if (*part1_seconds <= 0 || render_seconds <= 0 || tests_per_ray <= 0) {
    k.problems.push_back("no render times or test counts (--stats-json stats.json)");
    return k;
  }
  // The verdict rests on the work saved (intersection tests per ray),
  // which no machine load can change; the time speed-up of a render of a
  // few milliseconds is shown but is too noisy to fail anyone on.
  const double work_ratio = stat_ratio(part1.stats, "primitive_tests", "rays") / tests_per_ray;
  *speedup = *part1_seconds / render_seconds;
  k.metric = fmt("; BVH speed-up %.0fx", *speedup) + fmt(" (%.0fx fewer tests per ray)", work_ratio);
  if (work_ratio < bounds.min_speedup) {
    k.problems.push_back(fmt("the BVH saves too little: %.1fx fewer intersection tests per ray ", work_ratio) +
                         fmt("than testing every primitive (at least %.0fx expected)", bounds.min_speedup));
    return k;
  }
  k.credit = points;
  return k;
}

}  // namespace grader
