// The environment map's sampling density as a picture (--env-probability):
// for each texel of the map, the probability that the render's sampler of
// the map draws a direction in it. The course writes a debugging image of
// its distributions (probability_debug.png) whenever -e is given; this one
// is written only when asked for, and shows the probabilities themselves.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "common/environment.h"

namespace pt {

// The probability of each texel (row by row from the top, as the map's
// texels) under the sampler `--part part` gives the map: from part 8 on,
// part 8's distributions (the row's probability from marginal_cdf times the
// column's within the row from conditional_cdf, which is what
// sample_environment inverts); before, the uniform sampling of the sphere
// (the texel's solid angle over 4 pi). Empty distributions give all zeros
// and set *note to a warning. Throws std::runtime_error when part 8's
// distributions do not fit the map.
std::vector<double> environment_texel_probabilities(const EnvironmentMap& map, int part, std::string* note);

// The grey level of a texel's probability p on a map of n texels, on a
// logarithmic scale about the average texel's 1/n: 0 (black) at p <= 1/(1000 n)
// and for p = 0, 0.5 at p = 1/n, 1 (white) at p >= 1000/n.
double probability_grey(double p, size_t n);

// Those probabilities as an 8-bit grey PNG of the map's size, top row first.
std::vector<uint8_t> encode_environment_probability_png(const EnvironmentMap& map, int part, std::string* note);

}  // namespace pt
