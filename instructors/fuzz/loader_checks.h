// The readers under test and their contract: each input read by its reader
// (load_collada, Camera::load_settings, load_environment_map), then either
// checked for finite, consistent data (a loaded scene also gets a BVH and
// rays through it) or its refusal checked for the documented exception with
// a one-line message naming the file. Also fixed probes of the BVH build.
#pragma once
#include <string>

#include "instructors/fuzz/loader_inputs.h"

namespace fuzz {

// ---- Reading and checking ------------------------------------------------------

struct Outcome {
  std::string key;      // the class of result, for counting distinct outcomes
  std::string finding;  // non-empty: the reader broke its contract
};

// Reads the file at `path` as a `kind` and checks the outcome; `rng` draws
// the rays and lookups that probe what was read.
Outcome read_input(Kind kind, const std::string& path, Random& rng);

// Fixed probes of the BVH build at the edges of float (loader_checks.cpp);
// "" when they pass, else what went wrong.
std::string probe_bvh_extremes();

}  // namespace fuzz
