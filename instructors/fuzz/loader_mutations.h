// fuzz_loaders' mutations of a seed's bytes: byte-level ones for every kind,
// changes that keep the XML well formed for scenes, header integers for
// EXR files.
#pragma once
#include <string>
#include <vector>

#include "instructors/fuzz/loader_inputs.h"

namespace fuzz {

// Applies a few random mutations to `s`, a seed of `kind`; a splice takes
// its piece from another seed of the same kind in `pool`.
void mutate(Random& rng, std::string& s, Kind kind, const std::vector<Seed>& pool);

}  // namespace fuzz
