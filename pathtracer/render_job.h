// A whole render: load the scene, set up the camera, render with the parts
// selected by --part, write the images, print the course's console lines.
#pragma once
#include <string>

#include "image.h"
#include "options.h"
#include "scene.h"
#include "stats.h"

namespace pt {

struct RenderResult {
  ImageBuffer image;
  RayStats stats;
  double seconds = 0;
};

// Applies -r, -c, -b and -d to the scene's camera (in that order).
void configure_camera(Camera& cam, const RenderOptions& opts);

// Renders `scene` (camera already configured) as `opts.part` prescribes.
// Deterministic for a given opts.seed, whatever opts.threads is.
RenderResult render_scene(const Scene& scene, const RenderOptions& opts);

// Runs the whole job and returns the process exit code.
int run_render_job(const RenderOptions& opts);

}  // namespace pt
