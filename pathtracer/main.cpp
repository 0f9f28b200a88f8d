// pathtracer: command line -> scene -> render -> PNG.
#include "options.h"
#include "render_job.h"

int main(int argc, char** argv) {
  pt::RenderOptions opts;
  if (auto code = pt::parse_command_line(argc, argv, &opts)) return *code;
  return pt::run_render_job(opts);
}
