#include "pathtracer/render_job.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <new>
#include <stdexcept>

#include "stages/part1_raytracing/brute_force.h"
#include "pathtracer/bvh_overlay.h"
#include "pathtracer/env_probability.h"
#include "stages/part5_adaptive_sampling/adaptive_sampling.h"
#include "common/clock.h"
#include "common/collada.h"
#include "common/cost_splitting_intersector.h"
#include "common/image_io.h"
#include "common/json.h"
#include "stages/part1_raytracing/pixel_sampling.h"
#include "pathtracer/radiance.h"
#include "common/render_loop.h"
#include "stages/part9_depth_of_field/thin_lens.h"

namespace pt {

namespace {

// The outputs a render writes, in the order they are written.
std::vector<std::string> output_paths(const RenderOptions& opts) {
  const std::string png = output_png_path(opts);
  std::vector<std::string> paths = {png, rate_image_path(png)};
  if (!opts.output_pfm.empty()) paths.push_back(opts.output_pfm);
  if (!opts.stats_json.empty()) paths.push_back(opts.stats_json);
  if (!opts.env_probability.empty()) paths.push_back(opts.env_probability);
  return paths;
}

}  // namespace

void configure_camera(Camera& cam, const RenderOptions& opts) {
  cam.set_resolution(opts.width, opts.height);
  if (!opts.camera_settings.empty()) cam.load_settings(opts.camera_settings);
  cam.width = opts.width;
  cam.height = opts.height;
  if (opts.lens_radius_set) cam.lens_radius = opts.lens_radius;
  if (opts.focal_distance_set) cam.focal_distance = opts.focal_distance;
  // -b needs the thin lens of part 9; before, the camera is a pinhole.
  cam.thin_lens = opts.part >= 9 ? generate_ray_for_thin_lens : nullptr;
}

RenderResult render_scene(const Scene& scene, const RenderOptions& opts, const RenderHooks& hooks,
                          RenderCache* cache) {
  RenderResult result;
  ImageBuffer& img = result.image;
  const Camera& cam = scene.camera;

  // The pipeline of the chosen part. Part 1: every primitive tested, normal
  // shading. Part 2: the same shading through the BVH.
  std::unique_ptr<Intersector> geometry;
  const bool reuse = cache && cache->geometry && cache->part_at_least_2 == (opts.part >= 2) &&
                     cache->leaf == opts.bvh_max_leaf && cache->bins == opts.bvh_bins;
  if (reuse) {
    result.used_bvh = cache->used_bvh;
    result.bvh = cache->bvh;
  } else if (opts.part >= 2) {
    BVHOptions bo;
    bo.max_leaf_size = opts.bvh_max_leaf;
    bo.bins = opts.bvh_bins;
    auto bvh = std::make_unique<BVH>(scene, bo);
    result.used_bvh = true;
    result.bvh = bvh->build_stats();
    geometry = std::move(bvh);
  } else {
    geometry = std::make_unique<BruteForceIntersector>(scene);
  }
  if (cache && !reuse) {
    cache->geometry = std::move(geometry);
    cache->part_at_least_2 = opts.part >= 2;
    cache->leaf = opts.bvh_max_leaf;
    cache->bins = opts.bvh_bins;
    cache->used_bvh = result.used_bvh;
    cache->bvh = result.bvh;
  }
  const CostSplittingIntersector counted(cache ? *cache->geometry : *geometry);
  const Intersector& isect = counted;

  // Part 3: emission plus one bounce of direct light. Parts 4 and 5: paths
  // of up to -m bounces with Russian roulette (radiance.h).
  const RadianceFn radiance =
      hooks.wrap_radiance ? hooks.wrap_radiance(part_radiance(scene, isect, opts)) : part_radiance(scene, isect, opts);

  PixelRect rect{0, 0, opts.width, opts.height};
  if (opts.cell_set)
    rect = PixelRect{opts.cell_x, opts.cell_y, opts.cell_x + opts.cell_w, opts.cell_y + opts.cell_h};

  if (hooks.before_render) hooks.before_render(result);
  img = ImageBuffer(opts.width, opts.height);
  RenderLoopOptions loop;
  loop.threads = opts.threads;
  loop.progress = opts.progress;
  const auto t0 = Clock::now();
  // Part 5 samples each pixel adaptively (-a B T, the course's 32 0.05 by
  // default); earlier parts take -s samples everywhere.
  AdaptiveOptions adaptive;
  adaptive.batch = opts.adaptive_batch;
  adaptive.tolerance = opts.adaptive_tolerance;
  result.stats = render_tiles(rect, loop, [&](int x, int y) {
    if (hooks.before_pixel) hooks.before_pixel(x, y);
    if (opts.part >= 5) {
      int taken = 0;
      img.at(x, y) = raytrace_pixel_adaptive(cam, x, y, opts.samples_per_pixel, opts.seed, radiance, adaptive, &taken);
      img.samples[img.index(x, y)] = uint32_t(taken);
    } else {
      img.at(x, y) = raytrace_pixel(cam, x, y, opts.samples_per_pixel, opts.seed, radiance);
      img.samples[img.index(x, y)] = uint32_t(opts.samples_per_pixel);
    }
    if (hooks.after_pixel) hooks.after_pixel(x, y);
  });
  result.seconds = seconds_since(t0);
  return result;
}


namespace {

// The largest finite radiance of any channel of the image; 0 for black.
double max_radiance(const ImageBuffer& img) {
  double m = 0;
  for (const Color& c : img.pixels)
    for (int k = 0; k < 3; ++k)
      if (std::isfinite(c[k]) && c[k] > m) m = c[k];
  return m;
}

}  // namespace

std::string stats_json(const Scene& scene, const RenderOptions& opts, const RenderResult& r, double load_seconds) {
  const double rays = double(r.stats.rays());
  const auto per_ray = [&](uint64_t n) { return rays > 0 ? double(n) / rays : 0.0; };
  const auto seconds = [](double s) { return json_real(s, "%.6f"); };
  const auto ratio = [](double v) { return json_real(v, "%.4f"); };
  Json j = json_object();
  j.set("scene", json_text(opts.scene_path))
      .set("part", json_int(opts.part))
      .set("width", json_int(opts.width))
      .set("height", json_int(opts.height))
      .set("samples_per_pixel", json_int(opts.samples_per_pixel))
      .set("light_samples", json_int(opts.light_samples))
      .set("max_depth", json_int(opts.max_depth))
      .set("threads", json_int(opts.threads))
      .set("seed", json_count(opts.seed))
      .set("primitives", json_count(scene.num_primitives()))
      .set("triangles", json_count(scene.triangles.size()))
      .set("spheres", json_count(scene.spheres.size()))
      .set("lights", json_count(scene.lights.size()))
      .set("load_seconds", seconds(load_seconds))
      .set("bvh_build_seconds", seconds(r.used_bvh ? r.bvh.build_seconds : 0.0))
      .set("bvh_nodes", json_count(r.used_bvh ? r.bvh.nodes : 0))
      .set("bvh_leaves", json_count(r.used_bvh ? r.bvh.leaves : 0))
      .set("bvh_depth", json_int(r.used_bvh ? r.bvh.depth : 0))
      .set("bvh_sah_cost", ratio(r.used_bvh ? r.bvh.sah_cost : 0.0))
      .set("render_seconds", seconds(r.seconds))
      .set("rays", json_count(r.stats.rays()))
      .set("closest_queries", json_count(r.stats.closest_queries))
      .set("shadow_queries", json_count(r.stats.shadow_queries))
      .set("primitive_tests", json_count(r.stats.primitive_tests))
      .set("node_visits", json_count(r.stats.node_visits))
      .set("shadow_primitive_tests", json_count(r.stats.shadow_primitive_tests))
      .set("shadow_node_visits", json_count(r.stats.shadow_node_visits))
      .set("mrays_per_second", ratio(r.seconds > 0 ? rays / r.seconds * 1e-6 : 0.0))
      .set("tests_per_ray", ratio(per_ray(r.stats.primitive_tests)))
      .set("nodes_per_ray", ratio(per_ray(r.stats.node_visits)))
      .set("max_radiance", json_real(max_radiance(r.image)));
  return write_json(j);
}

int run_render_job(const RenderOptions& opts) {
  const std::string png = output_png_path(opts);
  // What the job is doing, for the message if memory runs out.
  std::string doing = "starting";
  try {
    for (const std::string& out : output_paths(opts)) check_output_path(out);
    if (!opts.env_map.empty() && !std::filesystem::is_regular_file(opts.env_map))
      throw std::runtime_error(opts.env_map + ": no such environment map");

    auto t0 = Clock::now();
    std::printf("[PathTracer] Collecting primitives... ");
    std::fflush(stdout);
    std::vector<std::string> warnings;
    Scene scene;
    doing = "loading " + opts.scene_path;
    try {
      scene = load_collada(opts.scene_path, &warnings);
    } catch (...) {
      std::printf("failed.\n");
      std::fflush(stdout);
      throw;
    }
    const double load_seconds = seconds_since(t0);
    std::printf("Done! (%.4f sec)\n", load_seconds);
    for (const std::string& w : warnings) std::fprintf(stderr, "pathtracer: warning: %s\n", w.c_str());
    std::shared_ptr<const EnvironmentMap> env_map;
    if (!opts.env_map.empty()) {
      doing = "reading the environment map " + opts.env_map;
      Light env;
      env.type = LightType::Environment;
      env_map = std::make_shared<const EnvironmentMap>(load_environment_map(opts.env_map));
      env.environment = env_map;
      scene.lights.push_back(env);
    }
    configure_camera(scene.camera, opts);

    if (opts.part >= 2)
      std::printf("[PathTracer] Building BVH from %zu primitives... ", scene.num_primitives());
    else
      std::printf("[PathTracer] Part 1: no BVH, every ray tests all %zu primitives.\n", scene.num_primitives());
    std::fflush(stdout);
    doing = "building the BVH of " + std::to_string(scene.num_primitives()) + " primitives";
    const std::string image_size = "-r " + std::to_string(opts.width) + " " + std::to_string(opts.height);
    // --bvh-boxes and --bvh-node draw the render's own BVH: keep it.
    const bool overlay = opts.bvh_boxes_depth >= 0 || opts.bvh_node >= 0;
    RenderCache kept;
    RenderHooks hooks;
    hooks.before_render = [&](const RenderResult& partial) {
      if (partial.used_bvh) std::printf("Done! (%.4f sec)\n", partial.bvh.build_seconds);
      std::printf("[PathTracer] Rendering... ");
      std::fflush(stdout);
      doing = image_size;
    };
    RenderResult r = render_scene(scene, opts, hooks, overlay ? &kept : nullptr);
    std::printf("100%%! (%.4fs)\n", r.seconds);
    const uint64_t rays = r.stats.rays();
    std::printf("[PathTracer] %s %llu rays.\n", r.used_bvh ? "BVH traced" : "Traced", (unsigned long long)rays);
    std::printf("[PathTracer] Average speed %.4f million rays per second.\n",
                r.seconds > 0 ? double(rays) / r.seconds * 1e-6 : 0.0);
    std::printf("[PathTracer] Averaged %f intersection tests per ray.\n",
                rays ? double(r.stats.primitive_tests) / double(rays) : 0.0);
    if (r.used_bvh)
      std::printf("[PathTracer] BVH: %zu nodes, %zu leaves, depth %d, SAH cost %.2f; %.2f nodes visited per ray.\n",
                  r.bvh.nodes, r.bvh.leaves, r.bvh.depth, r.bvh.sah_cost,
                  rays ? double(r.stats.node_visits) / double(rays) : 0.0);
    std::printf("[PathTracer] Saving to file: %s... ", png.c_str());
    std::fflush(stdout);
    // All the outputs or none: each goes to a temporary file first, and
    // they are renamed into place together.
    AtomicFileSet files;
    if (overlay) {
      // The boxes go into the PNG only: the PFM, the rate image and the
      // figures of --stats-json are the render's.
      const auto* bvh = dynamic_cast<const BVH*>(kept.geometry.get());
      if (!bvh) throw std::runtime_error("--bvh-boxes/--bvh-node: this render has no BVH");
      ImageBuffer drawn = r.image;
      std::string note;
      draw_bvh_overlay(drawn, scene.camera, *bvh, opts.bvh_boxes_depth, opts.bvh_node, &note);
      if (!note.empty()) std::fprintf(stderr, "pathtracer: warning: %s\n", note.c_str());
      files.add(png, encode_png(drawn));
    } else {
      files.add(png, encode_png(r.image));
    }
    files.add(rate_image_path(png), encode_rate_png(r.image, opts.samples_per_pixel));
    if (!opts.output_pfm.empty()) files.add(opts.output_pfm, encode_pfm(r.image));
    if (!opts.stats_json.empty()) {
      const std::string json = stats_json(scene, opts, r, load_seconds);
      files.add(opts.stats_json, std::vector<uint8_t>(json.begin(), json.end()));
    }
    if (!opts.env_probability.empty()) {
      // Where the render's sampler of the map draws its directions.
      std::string note;
      files.add(opts.env_probability, encode_environment_probability_png(*env_map, opts.part, &note));
      if (!note.empty()) std::fprintf(stderr, "pathtracer: warning: %s\n", note.c_str());
    }
    files.commit();
    std::printf("Done!\n");
    std::printf("[PathTracer] Job completed.\n");
    return 0;
  } catch (const std::bad_alloc&) {
    std::fflush(stdout);
    if (doing.rfind("-r ", 0) == 0)
      std::fprintf(stderr, "pathtracer: error: %s: out of memory for an image of this size; use a smaller -r\n",
                   doing.c_str());
    else
      std::fprintf(stderr, "pathtracer: error: out of memory while %s\n", doing.c_str());
    return 1;
  } catch (const std::exception& e) {
    std::fflush(stdout);
    std::fprintf(stderr, "pathtracer: error: %s\n", e.what());
    return 1;
  }
}

}  // namespace pt
