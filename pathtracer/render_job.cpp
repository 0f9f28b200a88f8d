#include "render_job.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>

#include "brute_force.h"
#include "collada.h"
#include "image_io.h"
#include "pixel_sampling.h"
#include "render_loop.h"
#include "shading.h"

namespace pt {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

std::string default_output_name(const std::string& scene_path) {
  return std::filesystem::path(scene_path).stem().string() + ".png";
}

// Fails early (before a long render) when an output cannot be written.
void check_writable(const std::string& path) {
  std::filesystem::path dir = std::filesystem::path(path).parent_path();
  if (dir.empty()) dir = ".";
  if (!std::filesystem::is_directory(dir))
    throw std::runtime_error(path + ": output folder " + dir.string() + " does not exist");
  if (access(dir.c_str(), W_OK) != 0)
    throw std::runtime_error(path + ": output folder " + dir.string() + " is not writable");
}

}  // namespace

void configure_camera(Camera& cam, const RenderOptions& opts) {
  cam.set_resolution(opts.width, opts.height);
  if (!opts.camera_settings.empty()) cam.load_settings(opts.camera_settings);
  cam.width = opts.width;
  cam.height = opts.height;
  if (opts.lens_radius_set) cam.lens_radius = opts.lens_radius;
  if (opts.focal_distance_set) cam.focal_distance = opts.focal_distance;
}

RenderResult render_scene(const Scene& scene, const RenderOptions& opts) {
  RenderResult result;
  result.image = ImageBuffer(opts.width, opts.height);
  ImageBuffer& img = result.image;
  const Camera& cam = scene.camera;

  // The pipeline of the chosen part. Parts 1: brute-force intersection and
  // normal shading.
  std::unique_ptr<Intersector> geometry = std::make_unique<BruteForceIntersector>(scene);
  const Intersector& isect = *geometry;
  const RadianceFn radiance = [&isect](const Ray& r, Rng&) { return normal_shading(isect, r); };

  PixelRect rect{0, 0, opts.width, opts.height};
  if (opts.cell_set)
    rect = PixelRect{opts.cell_x, opts.cell_y, opts.cell_x + opts.cell_w, opts.cell_y + opts.cell_h};

  RenderLoopOptions loop;
  loop.threads = opts.threads;
  loop.progress = opts.progress;
  const auto t0 = Clock::now();
  result.stats = render_tiles(rect, loop, [&](int x, int y) {
    img.at(x, y) = raytrace_pixel(cam, x, y, opts.samples_per_pixel, opts.seed, radiance);
    img.samples[img.index(x, y)] = uint32_t(opts.samples_per_pixel);
  });
  result.seconds = seconds_since(t0);
  return result;
}

int run_render_job(const RenderOptions& opts) {
  const std::string png = opts.output_png.empty() ? default_output_name(opts.scene_path) : opts.output_png;
  try {
    check_writable(png);
    check_writable(rate_image_path(png));
    if (!opts.output_pfm.empty()) check_writable(opts.output_pfm);

    auto t0 = Clock::now();
    std::printf("[PathTracer] Collecting primitives... ");
    std::fflush(stdout);
    std::vector<std::string> warnings;
    Scene scene;
    try {
      scene = load_collada(opts.scene_path, &warnings);
    } catch (...) {
      std::printf("failed.\n");
      std::fflush(stdout);
      throw;
    }
    std::printf("Done! (%.4f sec)\n", seconds_since(t0));
    for (const std::string& w : warnings) std::fprintf(stderr, "pathtracer: warning: %s\n", w.c_str());
    configure_camera(scene.camera, opts);

    std::printf("[PathTracer] Part %d: no BVH, every ray tests all %zu primitives.\n", opts.part,
                scene.num_primitives());
    std::printf("[PathTracer] Rendering... ");
    std::fflush(stdout);
    RenderResult r = render_scene(scene, opts);
    std::printf("100%%! (%.4fs)\n", r.seconds);
    const uint64_t rays = r.stats.rays();
    std::printf("[PathTracer] Traced %llu rays.\n", (unsigned long long)rays);
    std::printf("[PathTracer] Average speed %.4f million rays per second.\n",
                r.seconds > 0 ? double(rays) / r.seconds * 1e-6 : 0.0);
    std::printf("[PathTracer] Averaged %f intersection tests per ray.\n",
                rays ? double(r.stats.primitive_tests) / double(rays) : 0.0);

    std::printf("[PathTracer] Saving to file: %s... ", png.c_str());
    std::fflush(stdout);
    write_png(png, r.image);
    write_rate_png(rate_image_path(png), r.image, opts.samples_per_pixel);
    if (!opts.output_pfm.empty()) write_pfm(opts.output_pfm, r.image);
    std::printf("Done!\n");
    std::printf("[PathTracer] Job completed.\n");
    return 0;
  } catch (const std::exception& e) {
    std::fflush(stdout);
    std::fprintf(stderr, "pathtracer: error: %s\n", e.what());
    return 1;
  }
}

}  // namespace pt
