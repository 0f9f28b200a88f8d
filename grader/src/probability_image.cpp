#include "grader/src/probability_image.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include "grader/src/image_files.h"

namespace grader {

namespace {

// Grey (0 to 255) to log10 of the texel's probability over the average's.
double decades(float grey) { return 6.0 * double(grey) / 255.0 - 3.0; }

}  // namespace

Case with_probability_image(const Case& c) {
  if (c.kind != CaseKind::Probability) return c;
  Case p = c;
  p.options.push_back("--env-probability");
  p.options.push_back(kProbabilityImageFile);  // a name in the render's folder (render_argv)
  return p;
}

ProbabilityComparison compare_probability_images(const pt::ImageBuffer& candidate, const pt::ImageBuffer& reference) {
  if (candidate.width != reference.width || candidate.height != reference.height)
    throw std::runtime_error("the probability image is " + std::to_string(candidate.width) + " x " +
                             std::to_string(candidate.height) + ", the map " + std::to_string(reference.width) +
                             " x " + std::to_string(reference.height));
  ProbabilityComparison r;
  std::vector<double> diff;
  diff.reserve(reference.pixels.size());
  for (size_t i = 0; i < reference.pixels.size(); ++i) {
    const float g = reference.pixels[i].x;
    if (g <= 0.0f || g >= 255.0f) continue;  // clipped: black or white
    diff.push_back(decades(candidate.pixels[i].x) - decades(g));
  }
  r.compared = diff.size();
  if (diff.empty()) return r;
  std::vector<double> sorted = diff;
  std::nth_element(sorted.begin(), sorted.begin() + ptrdiff_t(sorted.size() / 2), sorted.end());
  r.shift = sorted[sorted.size() / 2];
  for (double d : diff) {
    const double a = std::fabs(d - r.shift);
    r.worst = std::max(r.worst, a);
    if (a > kProbabilityDecades) ++r.off;
  }
  return r;
}

Check check_probability_image(const std::string& candidate_png, const std::string& reference_png, double points) {
  Check k;
  k.name = "probability";
  k.credit = points;
  if (!std::filesystem::exists(candidate_png)) {
    k.problems.push_back("no probability image (--env-probability wrote nothing)");
    k.credit = 0;
    return k;
  }
  try {
    const ProbabilityComparison c =
        compare_probability_images(read_png_image(candidate_png), read_png_image(reference_png));
    char buf[256];
    std::snprintf(buf, sizeof buf, "probability image: %zu of %zu texels off by more than %.1f decades (allowed %.0f %%)",
                  c.off, c.compared, kProbabilityDecades, 100 * kProbabilityOffFraction);
    k.metric = std::string("; ") + buf;
    if (!c.passed()) {
      std::snprintf(buf, sizeof buf,
                    "the environment map's probability image differs from the reference's: %zu of %zu texels off by "
                    "more than a factor %.1f, up to %.1f decades (are texels weighted by their light times sin theta?)",
                    c.off, c.compared, std::pow(10.0, kProbabilityDecades), c.worst);
      k.problems.push_back(buf);
      k.credit = 0;
    }
  } catch (const std::exception& e) {
    k.problems.push_back(std::string("probability image: ") + e.what());
    k.credit = 0;
  }
  return k;
}

}  // namespace grader
