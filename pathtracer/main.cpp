// pathtracer: command line -> scene -> render -> PNG.
// (`pathtracer --probe FILE [--part N]`: the function checks, probe.h.)
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <new>
#include <string>

#include "pathtracer/options.h"
#include "pathtracer/probe.h"
#include "pathtracer/render_job.h"

namespace {

// `--probe FILE [--part N]`: every function of parts 1 to N (default: all
// this build implements) called on fixed inputs, the answers to FILE.
int probe_command(int argc, char** argv) {
  if (argc != 3 && !(argc == 5 && std::strcmp(argv[3], "--part") == 0)) {
    std::fprintf(stderr, "pathtracer: error: usage: pathtracer --probe FILE [--part N]\n");
    return 2;
  }
  int part = pt::kPartsBuilt;
  if (argc == 5) {
    char* end = nullptr;
    const long v = std::strtol(argv[4], &end, 10);
    if (*argv[4] == '\0' || *end != '\0' || v < 1 || v > pt::kPartsBuilt) {
      std::fprintf(stderr, "pathtracer: error: --part: expected a part from 1 to %d, got '%s'\n", pt::kPartsBuilt,
                   argv[4]);
      return 2;
    }
    part = int(v);
  }
  if (*argv[2] == '\0') {
    std::fprintf(stderr, "pathtracer: error: --probe: the path is empty\n");
    return 2;
  }
  return pt::probe::run_probes(argv[2], part);
}

}  // namespace

int main(int argc, char** argv) {
  // The render job reports its own errors; this is the last resort, so
  // that even a failure outside it is one line and an exit status of 1.
  try {
    if (argc >= 2 && std::strcmp(argv[1], "--probe") == 0) return probe_command(argc, argv);
    pt::RenderOptions opts;
    if (auto code = pt::parse_command_line(argc, argv, &opts)) return *code;
    return pt::run_render_job(opts);
  } catch (const std::bad_alloc&) {
    std::fflush(stdout);
    std::fprintf(stderr, "pathtracer: error: out of memory\n");
  } catch (const std::exception& e) {
    std::fflush(stdout);
    std::fprintf(stderr, "pathtracer: error: %s\n", e.what());
  } catch (...) {
    std::fflush(stdout);
    std::fprintf(stderr, "pathtracer: error: an unexpected failure\n");
  }
  return 1;
}
