// fuzz_loaders' seeds: files read whole, their kind from their extension,
// and small OpenEXR files written in every compression and layout.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "instructors/fuzz/loader_inputs.h"

namespace fuzz {

std::string slurp(const std::string& path);
Kind kind_of(const std::filesystem::path& p);
void write_exr_seeds(const std::string& dir, std::vector<Seed>* seeds);

}  // namespace fuzz
