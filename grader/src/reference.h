// A case's reference: B independent renders of the reference build at the
// case's own settings, reduced to per-pixel mean and variance, plus the
// costs recorded while making it. Stored in reference_images/<case>/:
//   mean.pfm, variance.pfm            radiance (variance of ONE render)
//   rate_mean.pfm, rate_variance.pfm  sample rates (adaptive cases)
//   meta.json                         command, runs, seeds, commit, times,
//                                     costs; written last (= complete)
#pragma once
#include <string>

#include "grader/src/case_list.h"
#include "common/json.h"
#include "grader/src/run_case.h"
#include "grader/src/scoring.h"

namespace grader {

struct Reference {
  ImageBuffer mean, variance;
  ImageBuffer rate_mean, rate_variance;  // adaptive cases (the rate in every channel)
  int runs = 0;
  bool deterministic = false;      // every run gave the same image
  Json meta;
};

// Loads the reference of `c` from `root`. Returns false with `why` when it
// is missing, incomplete or made for a different definition of the case.
bool load_reference(const std::string& root, const Case& c, Reference* ref, std::string* why);

struct MakeSettings {
  RunSettings run;      // the reference build
  int runs = 64;        // renders per case (2 when the image is deterministic)
  int jobs = 1;         // renders at a time
  uint64_t first_seed = 1000000;
  bool force = false;   // remake even when a matching reference exists
  std::string commit;   // recorded in the metadata
  std::string work_dir; // scratch space
  bool costs_only = false;  // retime_reference: re-measure the costs only, keep the recorded times
};

// Makes (or, unless forced, keeps) the reference of `c` in `root`/<name>.
// Returns false with a one-line reason when a reference render fails.
bool make_reference(const std::string& root, const Case& c, const MakeSettings& s, std::string* message);

// Re-measures the figures recorded in an existing reference's meta.json,
// the times (median of `runs` renders, one at a time, so that the machine
// is as quiet as it gets) and the costs per query, without touching its
// images. For references made on a busy machine, whose times would make
// every build look fast, and after the renderer counts something new.
// The costs are measured the way the grader renders the case (its renders
// at their share of -s, counts summed), never from one render at the whole
// -s: from part 5 on adaptive sampling makes the two differ. With
// s.costs_only, only the costs are re-measured and the times are kept.
bool retime_reference(const std::string& root, const Case& c, const MakeSettings& s, int runs, std::string* message);

}  // namespace grader
