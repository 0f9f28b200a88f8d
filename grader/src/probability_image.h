// The environment map's probability image (pathtracer --env-probability,
// the course's probability_debug.png), graded against the reference's.
// The picture is grey on a log scale: grey g (0 to 255) stands for a
// texel probability of 10^(6 g / 255 - 3) times the average texel's.
//
// The course asks for texels drawn in proportion to their light times
// sin theta (the solid angle of their row). "Their light" is any measure
// of a texel's brightness (luminance, the mean of r, g and b, the largest
// channel): on a coloured map these move a texel by up to about 0.3 of a
// decade against the luminance the reference uses, and a common factor
// moves them all. Leaving out sin theta moves each row by log10(1 / sin
// theta): past half a decade within 18 degrees of either pole, a fifth of
// the rows. So, after taking out the median difference (the common
// factor), a texel is off when it is more than kProbabilityDecades from
// the reference's, and the picture fails when more than
// kProbabilityOffFraction of the texels are off. Texels the reference
// shows black or white (beyond 1/1000 or 1000 times the average) are not
// compared: their value is clipped.
#pragma once
#include <cstddef>
#include <string>

#include "common/image.h"
#include "grader/src/case_list.h"
#include "grader/src/checks.h"

namespace grader {

// The picture's name in a render's folder and in the reference's.
constexpr const char* kProbabilityImageFile = "env_probability.png";

// A probability case with --env-probability added, asking its render for
// the map's picture (render_case writes it into the render's folder, as
// env_probability.png); any other case as it is.
Case with_probability_image(const Case& c);

constexpr double kProbabilityDecades = 0.5;
constexpr double kProbabilityOffFraction = 0.02;

struct ProbabilityComparison {
  size_t compared = 0;   // texels the reference shows neither black nor white
  size_t off = 0;        // of those, more than kProbabilityDecades from the reference
  double shift = 0;      // the median difference, in decades (taken out)
  double worst = 0;      // the largest difference after the shift, in decades
  bool passed() const { return compared > 0 && double(off) <= kProbabilityOffFraction * double(compared); }
};

// Both images as read by read_png_image (byte values; the grey in every
// channel). Throws std::runtime_error when their sizes differ.
ProbabilityComparison compare_probability_images(const pt::ImageBuffer& candidate, const pt::ImageBuffer& reference);

// The check of a `probability` case: the candidate's picture (written by
// its first render) against the reference's. A missing, unreadable or
// wrong-size picture, or one that fails the comparison, earns nothing.
Check check_probability_image(const std::string& candidate_png, const std::string& reference_png, double points);

}  // namespace grader
