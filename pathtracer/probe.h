// Function checks: each function a student writes, called on fixed inputs.
//
// `pathtracer --probe FILE` runs every check below with this build's own
// stage code and writes what each function returned to FILE (JSON). The
// grader runs it once when a build loses points, compares the figures with
// the reference build's (reference_images/probes.json) and names the
// functions that answer differently first among its hints: a render says
// that something is wrong, a function's answer on known inputs says where.
// The checks never score anything.
//
// A check is a list of numbers and how far each may be from the
// reference's: `abs` + `rel` |reference|. A function whose answer is
// fixed by its inputs (refract, microfacet_D, intersect_triangle) is
// compared to float round-off. A sampling function whose use of its random
// numbers is the student's choice (a thin lens mapped by the concentric
// disk, a microfacet sampler that swaps u1 and u2) is checked by what any
// correct sampler shares: averages over a stratified grid of its random
// numbers (the estimator's mean, the mean direction, where the rays
// focus), with a tolerance that such a grid's quadrature error fits in.
//
// Each function runs in a child process of its own (fork), so that one
// that crashes or never returns is reported as such and the others are
// still checked.
#pragma once
#include <string>
#include <vector>

namespace pt::probe {

struct Check {
  std::string name;            // what is checked, in a student's words ("refract: wi of 12 directions")
  std::vector<double> values;  // what the function gave (NaN and infinities are kept as such)
  double abs = 1e-5, rel = 1e-4;
};

// Adds `values` as one check.
inline void add(std::vector<Check>* out, const std::string& name, std::vector<double> values, double abs = 1e-5,
                double rel = 1e-4) {
  out->push_back(Check{name, std::move(values), abs, rel});
}

struct FunctionProbe {
  const char* function;  // as the hints name it: "refract", "BVH::build"
  int part;              // the part whose stage folder holds it
  std::vector<Check> (*run)();
};

// The checks of parts 1, 2 and 5 (probe_parts_1_2_5.cpp), of part 3's
// light estimators and part 4's path (probe_lighting.cpp: they need a
// scene) and of part 3's BSDF and parts 6-9 (probe_parts_3_6_9.cpp).
std::vector<FunctionProbe> probes_parts_1_2_5();
std::vector<FunctionProbe> probes_lighting();
std::vector<FunctionProbe> probes_parts_3_6_9();

// Runs every function's checks of parts <= max_part, each in a child
// process, and writes the JSON to `path`. Returns the exit status (0; 1
// with one line on stderr when the file cannot be written).
int run_probes(const std::string& path, int max_part);
// The same for the functions of `probes` (the tests' own list).
int run_probes(const std::string& path, int max_part, const std::vector<FunctionProbe>& probes);

}  // namespace pt::probe
