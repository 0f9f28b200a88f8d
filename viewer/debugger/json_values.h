// The debugger's results as values of the project's JSON (common/json.h),
// with two rules for the page on top of it. A float has 9 significant
// digits, which read back as the same float, and one that is NaN or
// infinite (JSON has no spelling for it) is the string "nan", "inf" or
// "-inf", so that the page can show it. A 64-bit seed is a string: a
// JavaScript number holds integers exactly only up to 2^53.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "common/json.h"
#include "common/ray.h"

namespace pt::debug {

Json json_float(float v);
// [a, b] on one line (the two uniform numbers of a sample).
Json json_pair(float a, float b);
// [x, y, z] on one line.
Json json_vec(const Vec3& v);
// {"origin", "direction", "min_t", "max_t", "depth"} on one line.
Json json_ray(const Ray& r);
Json json_seed(uint64_t seed);
// Items one per line; [] when there are none.
Json json_list(std::vector<Json> items);
Json json_strings(const std::vector<std::string>& items);

}  // namespace pt::debug
