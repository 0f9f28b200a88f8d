// A whole render: load the scene, set up the camera, render with the parts
// selected by --part, write the images, print the course's console lines.
#pragma once
#include <functional>
#include <memory>
#include <string>

#include "stages/part2_bvh/bvh.h"
#include "common/image.h"
#include "pathtracer/options.h"
#include "common/scene.h"
#include "common/stats.h"
#include "stages/part1_raytracing/pixel_sampling.h"

namespace pt {

struct RenderResult {
  ImageBuffer image;
  RayStats stats;
  double seconds = 0;          // rendering only
  bool used_bvh = false;
  BVHBuildStats bvh;           // when used_bvh
};

// What render_scene may keep between renders of one scene (the viewer's
// passes): the BVH (or part 1's brute force), built once and reused while
// the part's need of a BVH and the BVH settings stay the same.
struct RenderCache {
  std::unique_ptr<Intersector> geometry;
  bool part_at_least_2 = false;
  int leaf = 0, bins = 0;
  bool used_bvh = false;
  BVHBuildStats bvh;
};

// Applies -r, -c, -b and -d to the scene's camera (in that order), and
// gives it part 9's thin lens for --part 9 and later.
void configure_camera(Camera& cam, const RenderOptions& opts);

// What a caller of render_scene may add to a render (all optional).
struct RenderHooks {
  // Called once the acceleration structure is built and before the image
  // is allocated and the first pixel rendered (the console lines use it;
  // its RenderResult has no image yet).
  std::function<void(const RenderResult&)> before_render;
  // Called on the render thread right before and right after each pixel
  // (the viewer reads the thread's ray counters for its per-pixel maps).
  std::function<void(int x, int y)> before_pixel, after_pixel;
  // Given the part's radiance function, returns the one the pixel function
  // is handed (the viewer's passes reuse the samples of earlier passes).
  std::function<RadianceFn(RadianceFn)> wrap_radiance;
};

// Renders `scene` (camera already configured) as `opts.part` prescribes.
// Deterministic for a given opts.seed, whatever opts.threads is.
// `cache`, when given, keeps the acceleration structure for the next call
// with the same `scene`.
RenderResult render_scene(const Scene& scene, const RenderOptions& opts, const RenderHooks& hooks = {},
                          RenderCache* cache = nullptr);

// The render's figures as a JSON object (--stats-json).
std::string stats_json(const Scene& scene, const RenderOptions& opts, const RenderResult& r, double load_seconds);

// Runs the whole job and returns the process exit code. Every output path
// is checked before the scene is read; the outputs are then written all or
// nothing (see AtomicFileSet). Errors, running out of memory included, are
// one line on stderr and exit status 1.
int run_render_job(const RenderOptions& opts);

}  // namespace pt
