// A case's signature: the numbers that say how a graded build's result
// differs from the reference, in a form that noise hardly moves (ratios of
// means over whole regions, cost ratios, what went wrong), so that two
// builds with the same bug have nearly the same signature whatever their
// estimators' noise. The hints (hints.h) compare a build's signatures with
// those of the known bugs.
#pragma once
#include <map>
#include <string>

#include "common/image.h"
#include "grader/src/scoring.h"

namespace grader {

using pt::ImageBuffer;
using Signature = std::map<std::string, double>;

// The image's part of a signature, from the candidate's mean image and the
// reference's mean:
//   mean_ratio              sum of the candidate / sum of the reference
//   ratio_bright, ratio_dark, ratio_mid
//                           the same over the reference's brightest 10 %
//                           of pixels (lights, lit surfaces), its darkest
//                           30 % that are not black (shadows), the rest
//   ratio_edges, ratio_flat over pixels where the reference changes
//                           sharply (the top 15 % of its gradient) and the rest
//   ratio_top, ratio_bottom over the image's upper and lower halves
//   ratio_cell_R_C          the same over a kGridSide x kGridSide grid of
//                           the image (R: row from the top, C: column from
//                           the left): where in the picture the difference
//                           is (one corner of the box, the floor, the sky)
//   light_in_black          the candidate's mean where the reference is
//                           black (sky beyond a scene, the back of the cow),
//                           over the reference's whole mean
//   failed_fraction         pixel channels beyond the threshold
//   noise_ratio, mean_z_0..2 from the score
// A ratio whose reference sum is (nearly) zero is left out.
constexpr int kGridSide = 3;
// "ratio_cell_R_C".
std::string grid_key(int row, int column);

Signature image_signature(const ImageBuffer& candidate_mean, const ImageBuffer& reference_mean,
                          const ImageScore& score);

}  // namespace grader
