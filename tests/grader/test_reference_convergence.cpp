// Every committed reference has converged against its case's limits.
//
// A case fails a build whose image mean is more than L = z * SE from the
// reference's (z the image-mean test's threshold, SE the standard error of
// the difference: a build as noisy as the reference has the variance of
// one render at the case's settings, plus the reference's own over its B
// runs), and whose 8 x 8 blocks are more than z_block * SE_block off. A
// reference that is itself off by a sizeable share of L moves every
// build's z: correct builds fail more often than the run's budget, and a
// bias of that size in a build passes unseen. So:
//
//  1. The reference's standard error, from its own runs' variance, is at
//     most kFraction of L for the image mean (per channel) and for every
//     block: enough runs.
//  2. Its own variance can be wrong: where the light is found by rare
//     paths (a near-mirror metal lit by light sampling) B renders have
//     mostly not seen them, their mean sits low and their variance does
//     not say so. For those cases a long render with a lower-variance
//     estimator of the same expectation is summarised in
//     reference_images/long_renders.json (reference_images/long_render.py):
//     the reference's image mean is within kFraction of L of the long
//     render's, and so is every block's, beyond the two summaries' own
//     sampling error (kSamplingZ of their combined standard errors, a
//     level of about 1e-4 per block and channel). The long render must be
//     precise enough to say so: its image mean's standard error at most
//     kLongPrecision of L.
//
// Deterministic references (one value per pixel) have no noise to check.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "common/json.h"
#include "grader/src/case_list.h"
#include "grader/src/grade.h"
#include "grader/src/reference.h"
#include "grader/src/rules.h"
#include "grader/src/scoring.h"

using namespace grader;

namespace {

constexpr double kFraction = 0.1;
constexpr double kLongPrecision = 0.03;
constexpr double kSamplingZ = 3.9;

double value_from_top(const pt::ImageBuffer& img, int x, int y, int c) {
  return double(img.pixels[size_t(img.height - 1 - y) * size_t(img.width) + size_t(x)][c]);
}

// The limits and the reference's figures of one case, per channel and per block.
struct Figures {
  int bx = 0, by = 0;
  double mean[3] = {0, 0, 0}, mean_se[3] = {0, 0, 0}, mean_limit[3] = {0, 0, 0};
  std::vector<double> block, block_se, block_limit;  // (block * 3 + channel), blocks from the top-left
};

Figures figures(const Case& c, const Reference& ref, const Rules& rules) {
  const ScoreOptions so = case_score_options(c, ref, rules);
  const int w = ref.mean.width, h = ref.mean.height, bs = so.block_size;
  const double b = std::max(ref.runs, 1);
  Figures f;
  f.bx = (w + bs - 1) / bs;
  f.by = (h + bs - 1) / bs;
  const double z_mean = normal_two_sided_threshold(sidak_level(so.mean_alpha, 3));
  const double z_block =
      normal_two_sided_threshold(sidak_level(level_for_at_least(so.block_alpha, f.bx * f.by, so.min_blocks_to_fail), 3));
  double var_sum[3] = {0, 0, 0};
  f.block.assign(size_t(f.bx * f.by * 3), 0.0);
  f.block_se = f.block_limit = f.block;
  std::vector<double> block_var(f.block.size(), 0.0);
  std::vector<int> count(f.block.size(), 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int ch = 0; ch < 3; ++ch) {
        const size_t k = size_t(((y / bs) * f.bx + x / bs) * 3 + ch);
        const double m = value_from_top(ref.mean, x, y, ch), v = value_from_top(ref.variance, x, y, ch);
        f.mean[ch] += m;
        var_sum[ch] += v;
        f.block[k] += m;
        // The grader's floor on each pixel's variance, as its block test has it.
        block_var[k] += std::max(v, so.variance_floor);
        ++count[k];
      }
  const double n = double(w) * h;
  for (int ch = 0; ch < 3; ++ch) {
    f.mean[ch] /= n;
    const double v = var_sum[ch] / (n * n);  // one render's image mean
    f.mean_se[ch] = std::sqrt(v / b);
    f.mean_limit[ch] = z_mean * std::sqrt(v * (1 + 1 / b));
  }
  for (size_t k = 0; k < f.block.size(); ++k) {
    const double cnt = count[k], v = block_var[k] / (cnt * cnt);
    f.block[k] /= cnt;
    f.block_se[k] = std::sqrt(v / b);
    f.block_limit[k] = z_block * std::sqrt(v * (1 + 1 / b));
  }
  return f;
}

std::string root() { return std::string(PT_PROJECT_SCENES) + "/.."; }

}  // namespace

TEST_CASE("Every reference's standard error is at most a tenth of its case's limits", "[grader][references]") {
  const std::vector<Case> cases = read_cases(root() + "/grader/cases.txt");
  const Rules rules = make_rules(cases, root() + "/reference_images");
  int checked = 0;
  for (const Case& c : cases) {
    Reference ref;
    std::string why;
    REQUIRE(load_reference(root() + "/reference_images", c, &ref, &why));
    if (ref.deterministic) continue;
    INFO("case " << c.name << " (" << ref.runs << " runs)");
    const Figures f = figures(c, ref, rules);
    for (int ch = 0; ch < 3; ++ch) {
      INFO("channel " << ch << ": image mean " << f.mean[ch] << ", standard error " << f.mean_se[ch] << ", limit "
                      << f.mean_limit[ch]);
      CHECK(f.mean_se[ch] <= kFraction * f.mean_limit[ch]);
    }
    size_t worst = 0;
    for (size_t k = 0; k < f.block.size(); ++k)
      if (f.block_se[k] / f.block_limit[k] > f.block_se[worst] / f.block_limit[worst]) worst = k;
    INFO("block " << worst / 3 << " channel " << worst % 3 << ": standard error " << f.block_se[worst] << ", limit "
                  << f.block_limit[worst]);
    CHECK(f.block_se[worst] <= kFraction * f.block_limit[worst]);
    ++checked;
  }
  CHECK(checked >= 50);
}

TEST_CASE("References of rare-path cases agree with a long render of the same expectation", "[grader][references]") {
  const std::vector<Case> cases = read_cases(root() + "/grader/cases.txt");
  const Rules rules = make_rules(cases, root() + "/reference_images");
  const pt::Json summary = pt::read_json_file(root() + "/reference_images/long_renders.json");
  const pt::Json* long_cases = summary.get("cases");
  REQUIRE(long_cases);
  REQUIRE(!long_cases->members.empty());
  // Every case whose light is found by rare paths has a long render.
  for (const char* name : {"p7_alpha_0005"}) {
    INFO("case " << name);
    CHECK(long_cases->get(name));
  }
  for (const auto& [name, lr] : long_cases->members) {
    INFO("case " << name);
    const auto it = std::find_if(cases.begin(), cases.end(), [&](const Case& c) { return c.name == name; });
    REQUIRE(it != cases.end());
    Reference ref;
    std::string why;
    REQUIRE(load_reference(root() + "/reference_images", *it, &ref, &why));
    REQUIRE(!ref.deterministic);
    const Figures f = figures(*it, ref, rules);
    REQUIRE(lr.num("width") == ref.mean.width);
    REQUIRE(lr.num("height") == ref.mean.height);
    const pt::Json* mean = lr.get("mean");
    const pt::Json* mean_se = lr.get("mean_se");
    const pt::Json* blocks = lr.get("blocks");
    const pt::Json* blocks_se = lr.get("blocks_se");
    REQUIRE((mean && mean_se && blocks && blocks_se));
    REQUIRE(blocks->array.size() == size_t(f.bx * f.by));
    REQUIRE(blocks_se->array.size() == size_t(f.bx * f.by));
    for (int ch = 0; ch < 3; ++ch) {
      const double lm = mean->array[size_t(ch)].number, ls = mean_se->array[size_t(ch)].number;
      INFO("channel " << ch << ": reference " << f.mean[ch] << ", long render " << lm << " +- " << ls << " (x"
                      << f.mean[ch] / lm << "), limit " << f.mean_limit[ch]);
      CHECK(ls <= kLongPrecision * f.mean_limit[ch]);
      CHECK(std::fabs(f.mean[ch] - lm) <= kFraction * f.mean_limit[ch]);
    }
    int off = 0;
    std::string first;
    for (size_t b = 0; b < blocks->array.size(); ++b)
      for (int ch = 0; ch < 3; ++ch) {
        const size_t k = b * 3 + size_t(ch);
        const double lm = blocks->array[b].array[size_t(ch)].number, ls = blocks_se->array[b].array[size_t(ch)].number;
        const double allowed = kFraction * f.block_limit[k] + kSamplingZ * std::hypot(ls, f.block_se[k]);
        if (std::fabs(f.block[k] - lm) > allowed) {
          if (off++ == 0)
            first = "block " + std::to_string(b) + " channel " + std::to_string(ch) + ": reference " +
                    std::to_string(f.block[k]) + ", long render " + std::to_string(lm) + ", allowed " +
                    std::to_string(allowed);
        }
      }
    INFO(off << " blocks off; the first: " << first);
    CHECK(off == 0);
  }
}
