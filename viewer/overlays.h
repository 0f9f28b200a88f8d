// The render mode's images as the page draws them, 8-bit RGB rows from the
// top: the render itself, the overlays of a frame (sample rate, tests per
// ray) and the grader's difference with a case's reference.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "grader/src/hints.h"
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

// The frame as the command line's PNG looks (8-bit RGB rows from the top),
// and that PNG file, made from the frame's payload without a copy of the
// image.
std::vector<uint8_t> frame_rgb(const Frame& f);
std::vector<uint8_t> frame_png(const Frame& f);

// Bytes [offset, offset + n) of the frame as the command line's PFM file
// (encode_pfm's bytes), and that file's size: a download is streamed.
size_t frame_pfm_size(const Frame& f);
void frame_pfm_bytes(const Frame& f, size_t offset, size_t n, char* out);

// When frame `f` is an earlier pass of a render of case `vc`'s settings
// (`opts`, the render's, has the case's sample count; the frame fewer):
// "difference shown when the render reaches N samples (now n)". Empty
// otherwise: the frame is the case's, or the render is not.
std::string difference_pending(const Frame& f, const RenderOptions& opts, const ViewerCase& vc);

// The grader's comparison of frame `f` of a job run with `opts` against
// case `vc`'s reference in `reference_dir`: |z| per pixel (black to white
// at the threshold, red beyond), scale the threshold, and the verdict;
// when the render differs, the known bugs of `catalogue` nearest to it on
// this case (grader/src/hints.h, as `grader compare` names them).
// Throws BadRequest when the render is not the case's (409), the
// reference is missing (404) or the image has NaN or infinite pixels (422).
struct Difference {
  Overlay picture;
  std::string verdict;
  bool differs = false;
  std::vector<grader::Hint> hints;  // nearest first; point into the catalogue
  bool hints_known = false;         // the catalogue had bugs to compare with
};
Difference difference_overlay(const Frame& f, const RenderOptions& opts, const ViewerCase& vc,
                              const std::string& reference_dir, const grader::Catalogue& catalogue,
                              const grader::CaseGroups& groups);

// The likely causes as the page reads them: {"hints": [{"text": the bug's
// words with the render's figures, "function", "file", "readme": the
// README's path, "section": its section in plain words}, ...]}, with
// "note": the line that no known bug is close when the render differs and
// none is. Empty "hints" and no note when it matches.
std::string hints_json(const Difference& d);

}  // namespace pt::viewer
