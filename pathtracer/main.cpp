// pathtracer: command line -> scene -> render -> PNG.
#include <cstdio>
#include <exception>
#include <new>

#include "pathtracer/options.h"
#include "pathtracer/render_job.h"

int main(int argc, char** argv) {
  // The render job reports its own errors; this is the last resort, so
  // that even a failure outside it is one line and an exit status of 1.
  try {
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
