// Where a worker's code was, by name: the places of a crash or stall
// report (worker_watch.h) turned into the function of the project's that
// was running, with its file and line where the build has debug
// information. The worker is this program, so the server reads its own
// file: with addr2line (binutils, which every C++ build machine has), or
// else with the program's exported symbols (dladdr; function names only).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace pt::viewer {

// One thread's place in a report: "pc=<hex|-> stack=<hex>,<hex>,...",
// offsets into the program's file.
struct ThreadPlace {
  bool pc_in_code = false;  // the thread was running the program's code (not a library's, not waiting)
  uint64_t pc = 0;
  std::vector<uint64_t> stack;  // addresses found on its stack, innermost first
};
bool parse_thread_place(const std::string& text, ThreadPlace* out);

// A function of the project's: "intersect_triangle", "BVH::intersect";
// `where` is "stages/part1_raytracing/triangle.cpp:23" (from the source
// folder) when the build has debug information, else empty.
struct NamedPlace {
  std::string function, where;
};

// The innermost function of the project's among the threads' places:
// from a thread that was running the program's code if there is one
// (the others wait), its program counter first (with the functions
// inlined there), then its stack; the worker's own machinery is skipped.
// Empty when none is found. `exe` is the program's file.
NamedPlace innermost_function(const std::string& exe, const std::string& source_dir,
                              const std::vector<ThreadPlace>& threads);

// "pt::BVH::intersect(pt::Ray&, pt::Hit*) const" -> "BVH::intersect": the
// name without its parameters and the project's namespaces; empty for
// functions outside the project (the standard library, libc) and for the
// worker's machinery.
std::string project_function(const std::string& demangled);

}  // namespace pt::viewer
