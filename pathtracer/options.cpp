#include "pathtracer/options.h"

#include <CLI/CLI.hpp>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <system_error>
#include <vector>

#include "common/image_io.h"

namespace pt {

namespace {

// A number flag's value: finite and within [lo, hi]. (CLI11's own Range
// lets NaN through.)
CLI::Validator finite_in(double lo, double hi) {
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        double v = 0;
        if (!CLI::detail::lexical_cast(text, v)) return "'" + text + "' is not a number";
        if (!std::isfinite(v)) return "'" + text + "' is not a finite number";
        if (v < lo || v > hi) {
          char range[96];
          std::snprintf(range, sizeof range, "[%g, %g]", lo, hi);
          return "'" + text + "' is outside " + range;
        }
        return std::string();
      },
      "", "finite");
}

// A non-negative decimal integer that fits in 64 bits.
bool parse_seed(const std::string& text, uint64_t* out) {
  if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos) return false;
  const auto r = std::from_chars(text.data(), text.data() + text.size(), *out);
  return r.ec == std::errc() && r.ptr == text.data() + text.size();
}

// Whether two paths name the same file: the same inode when both exist,
// else the same absolute path once "." and ".." are resolved and symbolic
// links followed as far as they exist.
bool same_file(const std::string& a, const std::string& b) {
  namespace fs = std::filesystem;
  std::error_code ea, eb;
  if (fs::exists(a, ea) && fs::exists(b, eb)) {
    std::error_code ec;
    if (fs::equivalent(a, b, ec)) return true;
  }
  const fs::path ca = fs::weakly_canonical(fs::absolute(a, ea), ea);
  const fs::path cb = fs::weakly_canonical(fs::absolute(b, eb), eb);
  return !ea && !eb && ca == cb;
}

// One file the render reads or writes, for the same-file checks.
struct PathUse {
  std::string path;
  std::string flag;  // how the message starts: "-f out.png"
  std::string lead;  // "" or "its sample-rate image out_rate.png is "
  std::string role;  // how other messages name it
};

// Refuses an output that names an input or another output. Returns the
// message, or an empty string when every path is distinct.
std::string path_conflict(const RenderOptions& o) {
  const std::string png = output_png_path(o);
  const std::string png_flag = o.output_png.empty() ? "the default output " + png : "-f " + png;
  const std::string rate = rate_image_path(png);
  std::vector<PathUse> inputs = {{o.scene_path, "", "", "the scene file (" + o.scene_path + ")"}};
  if (!o.camera_settings.empty())
    inputs.push_back({o.camera_settings, "", "", "the camera settings file (-c " + o.camera_settings + ")"});
  if (!o.env_map.empty()) inputs.push_back({o.env_map, "", "", "the environment map (-e " + o.env_map + ")"});
  std::vector<PathUse> outputs = {
      {png, png_flag, "", "the output PNG (" + png_flag + ")"},
      {rate, png_flag, "its sample-rate image " + rate + " is ", "the sample-rate image of " + png_flag}};
  if (!o.output_pfm.empty()) outputs.push_back({o.output_pfm, "--pfm " + o.output_pfm, "", "--pfm " + o.output_pfm});
  if (!o.stats_json.empty())
    outputs.push_back({o.stats_json, "--stats-json " + o.stats_json, "", "--stats-json " + o.stats_json});
  if (!o.env_probability.empty())
    outputs.push_back({o.env_probability, "--env-probability " + o.env_probability, "",
                       "--env-probability " + o.env_probability});
  for (size_t i = 0; i < outputs.size(); ++i) {
    const PathUse& out = outputs[i];
    for (const PathUse& in : inputs)
      if (same_file(out.path, in.path))
        return out.flag + ": " + out.lead + "the same file as " + in.role + "; refusing to overwrite it";
    for (size_t j = 0; j < i; ++j)
      if (same_file(out.path, outputs[j].path))
        return out.flag + ": " + out.lead + "the same file as " + outputs[j].role;
  }
  return "";
}

}  // namespace

std::string output_png_path(const RenderOptions& opts) {
  if (!opts.output_png.empty()) return opts.output_png;
  return std::filesystem::path(opts.scene_path).stem().string() + ".png";
}

namespace {

// What the command line gives before it is checked and put into
// RenderOptions.
struct RawFlags {
  std::vector<int> res, cell;
  std::vector<std::string> adaptive;
  std::string seed_text;
  int accumulate = 1;
  bool no_rr = false;
  bool no_progress = false;
};

// The course's flags, then the ones this renderer adds (the README's flag
// table lists the same, checked against -h by a test).
void add_flags(CLI::App& app, RenderOptions* o, RawFlags* raw) {
  app.add_option("-s", o->samples_per_pixel, "Camera rays per pixel (the maximum with adaptive sampling)")
      ->check(CLI::Range(1, 1 << 20))->default_val(1);
  app.add_option("-l", o->light_samples, "Samples per area light")->check(CLI::Range(1, 1 << 16))->default_val(1);
  app.add_option("-t", o->threads, "Render threads")->check(CLI::Range(1, 1024))->default_val(1);
  app.add_option("-m", o->max_depth, "Maximum ray depth")->check(CLI::Range(0, 1 << 20))->default_val(1);
  app.add_option("-o", raw->accumulate, "Accumulate bounces: 1 sums bounces 0..m, 0 returns only the m-th")
      ->check(CLI::Range(0, 1 << 20))->default_val(1);
  app.add_option("-e", o->env_map, "Environment map (OpenEXR)");
  app.add_option("-b", o->lens_radius, "Thin-lens aperture radius")->check(finite_in(0.0, 1e6));
  app.add_option("-d", o->focal_distance, "Focal distance")->check(finite_in(1e-6, 1e9));
  app.add_option("-f", o->output_png, "Output PNG (default: <scene name>.png)");
  app.add_option("-r", raw->res, "Output width and height")->expected(2)->type_name("W H");
  app.add_option("-c", o->camera_settings, "Camera settings file");
  app.add_option("-a", raw->adaptive, "Adaptive sampling: samples per batch and tolerance")
      ->expected(2)->type_name("B T");
  app.add_flag("-H", o->hemisphere_sampling, "Direct lighting by uniform hemisphere sampling");
  app.add_flag("--bsdf-hemisphere", o->bsdf_hemisphere,
               "Part 7 on: sample microfacet BSDFs by cosine-weighted directions, not by their NDF");
  app.add_option("--env-probability", o->env_probability,
                 "Write the PNG of where the environment map (-e) is sampled: each texel's probability");
  app.add_option("-p", raw->cell, "Render only the cell [X,X+DX) x [Y,Y+DY), (0,0) bottom-left")
      ->expected(4)->type_name("X Y DX DY");
  app.add_option("--part", o->part, "Render what the assignment gives after part N (1-9)")
      ->check(CLI::Range(1, kPartsBuilt))->default_val(kPartsBuilt);
  app.add_option("--seed", raw->seed_text, "Image seed, 0 to 2^64-1 (renders are reproducible for a given seed)")
      ->type_name("N");
  app.add_option("--pfm", o->output_pfm, "Also write linear radiance to this PFM file");
  app.add_option("--stats-json", o->stats_json, "Write the render's figures (times, rays, tests, largest radiance) as JSON");
  app.add_option("--bvh-leaf", o->bvh_max_leaf, "Most primitives per BVH leaf")->check(CLI::Range(1, 255))->default_val(4);
  app.add_option("--bvh-bins", o->bvh_bins, "SAH bins per axis when building the BVH")->check(CLI::Range(2, 64))->default_val(12);
  app.add_option("--bvh-boxes", o->bvh_boxes_depth,
                 "Draw the boxes of every BVH node at depth D (root 0) over the PNG, in yellow")
      ->check(CLI::Range(0, 1 << 20))->type_name("D");
  app.add_option("--bvh-node", o->bvh_node,
                 "Draw BVH node N's box (white) and its children's (red, blue) over the PNG")
      ->check(CLI::Range(0LL, 1LL << 40))->type_name("N");
  app.add_flag("--no-rr", raw->no_rr, "Part 4: no Russian roulette, every path runs to -m bounces");
  app.add_flag("--direct-only", o->direct_only, "Part 4: only emission and direct light (bounces 0 and 1)");
  app.add_flag("--indirect-only", o->indirect_only, "Part 4: only indirect light (bounces 2 to -m)");
  app.add_flag("--course-area-pdf", o->course_area_pdf,
               "Use the course's area-light pdf (off by the distance to the light) to reproduce its images");
  app.add_flag("--no-progress", raw->no_progress, "Never draw the progress bar");
  app.add_option("scene", o->scene_path, "Scene file (.dae)")->required();
}

// -r W H into o; an error message, or "".
std::string apply_size(const std::vector<int>& res, RenderOptions* o) {
  if (res.empty()) return "";
  if (res[0] < 1 || res[1] < 1 || res[0] > 16384 || res[1] > 16384)
    return "-r: width and height must be between 1 and 16384, got " + std::to_string(res[0]) + " " +
           std::to_string(res[1]);
  if ((long long)res[0] * res[1] > kMaxImagePixels)
    return "-r " + std::to_string(res[0]) + " " + std::to_string(res[1]) + ": the image would have " +
           std::to_string((long long)res[0] * res[1]) + " pixels; at most " + std::to_string(kMaxImagePixels) +
           " (e.g. 8192 x 4096) fit the renderer's memory limit";
  o->width = res[0];
  o->height = res[1];
  return "";
}

// -a B T into o; an error message, or "".
std::string apply_adaptive(const std::vector<std::string>& adaptive, RenderOptions* o) {
  if (adaptive.empty()) return "";
  try {
    size_t u1 = 0, u2 = 0;
    const int b = std::stoi(adaptive[0], &u1);
    const double t = std::stod(adaptive[1], &u2);
    if (u1 != adaptive[0].size() || u2 != adaptive[1].size()) throw std::invalid_argument("");
    if (b < 1 || b > (1 << 20)) return "-a: samples per batch must be at least 1, got " + adaptive[0];
    if (!(t > 0) || !std::isfinite(t)) return "-a: tolerance must be a positive number, got " + adaptive[1];
    o->adaptive_batch = b;
    o->adaptive_tolerance = t;
    o->adaptive_set = true;
  } catch (const std::exception&) {
    return "-a: expected an integer batch size and a number, got '" + adaptive[0] + " " + adaptive[1] + "'";
  }
  return "";
}

// -p X Y DX DY into o (after -r: the cell must lie in the image); an error
// message, or "".
std::string apply_cell(const std::vector<int>& cell, RenderOptions* o) {
  if (cell.empty()) return "";
  // In 64 bits: X + DX must not wrap around.
  const long long x = cell[0], y = cell[1], dx = cell[2], dy = cell[3];
  if (x < 0 || y < 0 || dx < 1 || dy < 1 || x + dx > o->width || y + dy > o->height)
    return "-p: the cell must lie inside the " + std::to_string(o->width) + "x" + std::to_string(o->height) +
           " image and be at least 1x1";
  o->cell_set = true;
  o->cell_x = cell[0];
  o->cell_y = cell[1];
  o->cell_w = cell[2];
  o->cell_h = cell[3];
  return "";
}

// The checks across flags, and the flags' raw values into o, in the order
// their messages are given; an error message, or "".
std::string apply_flags(const CLI::App& app, const RawFlags& raw, RenderOptions* o) {
  o->accumulate_bounces = raw.accumulate != 0;
  o->russian_roulette = !raw.no_rr;
  if (o->direct_only && o->indirect_only) return "--direct-only and --indirect-only exclude each other";
  o->progress = !raw.no_progress;
  o->lens_radius_set = app.count("-b") > 0;
  o->focal_distance_set = app.count("-d") > 0;
  // An empty path would otherwise mean "none" (-e) or fail late.
  for (const auto& [flag, value] : {std::pair<const char*, const std::string*>{"-e", &o->env_map},
                                    {"-f", &o->output_png}, {"-c", &o->camera_settings},
                                    {"--pfm", &o->output_pfm}, {"--stats-json", &o->stats_json},
                                    {"--env-probability", &o->env_probability}})
    if (app.count(flag) > 0 && value->empty()) return std::string(flag) + ": the path is empty";
  if (o->scene_path.empty()) return "scene: the path is empty";
  if (app.count("--seed") > 0 && !parse_seed(raw.seed_text, &o->seed))
    return "--seed: expected an integer from 0 to 18446744073709551615, got '" + raw.seed_text + "'";
  if (std::string e = apply_size(raw.res, o); !e.empty()) return e;
  if (std::string e = apply_adaptive(raw.adaptive, o); !e.empty()) return e;
  if (std::string e = apply_cell(raw.cell, o); !e.empty()) return e;
  if ((o->bvh_boxes_depth >= 0 || o->bvh_node >= 0) && o->part < 2)
    return std::string(o->bvh_boxes_depth >= 0 ? "--bvh-boxes" : "--bvh-node") +
           " draws the BVH's boxes: it needs --part 2 or later (part 1 has no BVH)";
  if (!o->env_probability.empty() && o->env_map.empty())
    return "--env-probability draws where the environment map is sampled: it needs -e";
  if (!o->env_probability.empty() && o->part < 3)
    return "--env-probability draws where the environment map is sampled: it needs --part 3 or later "
           "(parts 1 and 2 do not light the scene)";
  if (o->part > kPartsBuilt)
    return "--part " + std::to_string(o->part) + ": this build implements parts 1 to " + std::to_string(kPartsBuilt) +
           " only";
  return path_conflict(*o);
}

}  // namespace

std::optional<int> parse_command_line(int argc, char** argv, RenderOptions* o) {
  CLI::App app{
      "pathtracer: the CS184 PathTracer reference renderer.\n"
      "Renders a COLLADA scene (.dae) to a PNG. Flags follow the course's command line."};
  app.get_formatter()->column_width(28);
  app.set_help_flag("-h,--help", "Print this help and exit");
  RawFlags raw;
  add_flags(app, o, &raw);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    std::printf("%s", app.help().c_str());
    return 0;
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "pathtracer: error: %s (run 'pathtracer -h' for usage)\n", e.what());
    return 2;
  }
  const std::string error = apply_flags(app, raw, o);
  if (error.empty()) return std::nullopt;
  std::fprintf(stderr, "pathtracer: error: %s\n", error.c_str());
  return 2;
}

}  // namespace pt
