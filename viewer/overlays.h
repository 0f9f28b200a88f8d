// The render mode's images as the page draws them, 8-bit RGB rows from the
// top: the render itself, the overlays of a frame (sample rate, tests per
// ray) and the grader's difference with a case's reference.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "pathtracer/options.h"
#include "viewer/viewer_cases.h"
#include "viewer/workers.h"

namespace pt::viewer {

struct Overlay {
  std::vector<uint8_t> rgb;
  double scale = 0;  // what white (or red) stands for; 0 when nothing is scaled
};

// `kind` of frame `f` of a render of `target` samples per pixel: "render"
// (or empty), "rate" (the course's rate image: samples taken / -s) or
// "tests" (tests per ray, red at the image's largest). Throws BadRequest
// for another kind.
Overlay frame_overlay(const Frame& f, const std::string& kind, int target);

// The grader's comparison of frame `f` of a job run with `opts` against
// case `vc`'s reference in `reference_dir`: |z| per pixel (black to white
// at the threshold, red beyond), scale the threshold, and the verdict.
// Throws BadRequest when the render is not the case's (409), the
// reference is missing (404) or the image has NaN or infinite pixels (422).
struct Difference {
  Overlay picture;
  std::string verdict;
};
Difference difference_overlay(const Frame& f, const RenderOptions& opts, const ViewerCase& vc,
                              const std::string& reference_dir);

}  // namespace pt::viewer
