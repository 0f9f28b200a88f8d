#include "options.h"

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <vector>

namespace pt {

std::optional<int> parse_command_line(int argc, char** argv, RenderOptions* o) {
  CLI::App app{
      "pathtracer: the CS184 PathTracer reference renderer.\n"
      "Renders a COLLADA scene (.dae) to a PNG. Flags follow the course's command line."};
  app.get_formatter()->column_width(28);
  app.set_help_flag("-h,--help", "Print this help and exit");

  std::vector<int> res, cell;
  std::vector<std::string> adaptive;
  int accumulate = 1;

  app.add_option("-s", o->samples_per_pixel, "Camera rays per pixel (the maximum with adaptive sampling)")
      ->check(CLI::Range(1, 1 << 20))->default_val(1);
  app.add_option("-l", o->light_samples, "Samples per area light")->check(CLI::Range(1, 1 << 16))->default_val(1);
  app.add_option("-t", o->threads, "Render threads")->check(CLI::Range(1, 1024))->default_val(1);
  app.add_option("-m", o->max_depth, "Maximum ray depth")->check(CLI::Range(0, 1 << 20))->default_val(1);
  app.add_option("-o", accumulate, "Accumulate bounces: 1 sums bounces 0..m, 0 returns only the m-th")
      ->check(CLI::Range(0, 1 << 20))->default_val(1);
  app.add_option("-e", o->env_map, "Environment map (OpenEXR)");
  app.add_option("-b", o->lens_radius, "Thin-lens aperture radius")->check(CLI::Range(0.0, 1e6));
  app.add_option("-d", o->focal_distance, "Focal distance")->check(CLI::Range(1e-6, 1e9));
  app.add_option("-f", o->output_png, "Output PNG (default: <scene name>.png)");
  app.add_option("-r", res, "Output width and height")->expected(2)->type_name("W H");
  app.add_option("-c", o->camera_settings, "Camera settings file");
  app.add_option("-a", adaptive, "Adaptive sampling: samples per batch and tolerance")
      ->expected(2)->type_name("B T");
  app.add_flag("-H", o->hemisphere_sampling, "Direct lighting by uniform hemisphere sampling");
  app.add_option("-p", cell, "Render only the cell [X,X+DX) x [Y,Y+DY), (0,0) bottom-left")
      ->expected(4)->type_name("X Y DX DY");
  app.add_option("--part", o->part, "Render what the assignment gives after part N (1-5)")
      ->check(CLI::Range(1, 5))->default_val(kPartsBuilt);
  app.add_option("--seed", o->seed, "Image seed (renders are reproducible for a given seed)");
  app.add_option("--pfm", o->output_pfm, "Also write linear radiance to this PFM file");
  app.add_option("--stats-json", o->stats_json, "Write the render's figures (times, rays, tests) as JSON");
  app.add_option("--bvh-leaf", o->bvh_max_leaf, "Most primitives per BVH leaf")->check(CLI::Range(1, 255))->default_val(4);
  app.add_option("--bvh-bins", o->bvh_bins, "SAH bins per axis when building the BVH")->check(CLI::Range(2, 64))->default_val(12);
  bool no_rr = false;
  app.add_flag("--no-rr", no_rr, "Part 4: no Russian roulette, every path runs to -m bounces");
  app.add_flag("--direct-only", o->direct_only, "Part 4: only emission and direct light (bounces 0 and 1)");
  app.add_flag("--indirect-only", o->indirect_only, "Part 4: only indirect light (bounces 2 to -m)");
  app.add_flag("--course-area-pdf", o->course_area_pdf,
               "Use the course's area-light pdf (off by the distance to the light) to reproduce its images");
  bool no_progress = false;
  app.add_flag("--no-progress", no_progress, "Never draw the progress bar");
  app.add_option("scene", o->scene_path, "Scene file (.dae)")->required();

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    std::printf("%s", app.help().c_str());
    return 0;
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "pathtracer: error: %s (run 'pathtracer -h' for usage)\n", e.what());
    return 2;
  }

  auto fail = [](const std::string& msg) {
    std::fprintf(stderr, "pathtracer: error: %s\n", msg.c_str());
    return std::optional<int>(2);
  };
  o->accumulate_bounces = accumulate != 0;
  o->russian_roulette = !no_rr;
  if (o->direct_only && o->indirect_only) return fail("--direct-only and --indirect-only exclude each other");
  o->progress = !no_progress;
  o->lens_radius_set = app.count("-b") > 0;
  o->focal_distance_set = app.count("-d") > 0;
  if (!res.empty()) {
    if (res[0] < 1 || res[1] < 1 || res[0] > 16384 || res[1] > 16384)
      return fail("-r: width and height must be between 1 and 16384, got " + std::to_string(res[0]) + " " +
                  std::to_string(res[1]));
    o->width = res[0];
    o->height = res[1];
  }
  if (!adaptive.empty()) {
    try {
      size_t u1 = 0, u2 = 0;
      const int b = std::stoi(adaptive[0], &u1);
      const double t = std::stod(adaptive[1], &u2);
      if (u1 != adaptive[0].size() || u2 != adaptive[1].size()) throw std::invalid_argument("");
      if (b < 1 || b > (1 << 20)) return fail("-a: samples per batch must be at least 1, got " + adaptive[0]);
      if (!(t > 0) || !std::isfinite(t)) return fail("-a: tolerance must be a positive number, got " + adaptive[1]);
      o->adaptive_batch = b;
      o->adaptive_tolerance = t;
      o->adaptive_set = true;
    } catch (const std::exception&) {
      return fail("-a: expected an integer batch size and a number, got '" + adaptive[0] + " " + adaptive[1] + "'");
    }
  }
  if (!cell.empty()) {
    if (cell[0] < 0 || cell[1] < 0 || cell[2] < 1 || cell[3] < 1 || cell[0] + cell[2] > o->width ||
        cell[1] + cell[3] > o->height)
      return fail("-p: the cell must lie inside the " + std::to_string(o->width) + "x" +
                  std::to_string(o->height) + " image and be at least 1x1");
    o->cell_set = true;
    o->cell_x = cell[0];
    o->cell_y = cell[1];
    o->cell_w = cell[2];
    o->cell_h = cell[3];
  }
  if (o->part > kPartsBuilt)
    return fail("--part " + std::to_string(o->part) + ": this build implements parts 1 to " +
                std::to_string(kPartsBuilt) + " only");
  return std::nullopt;
}

}  // namespace pt
