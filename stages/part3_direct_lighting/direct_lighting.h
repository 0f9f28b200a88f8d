// Part 3: direct lighting, by uniform hemisphere sampling (-H) and by
// sampling the lights (importance sampling).
#pragma once
#include <vector>

#include "common/intersector.h"
#include "common/ray.h"
#include "common/rng.h"
#include "common/scene.h"

namespace pt {

// What shading reads of the scene: its materials and lights. The render
// gives copies of the scene's, with each material's BSDF and each
// environment light's sampler set for the parts it renders (see
// common/bsdf.h); a Scene converts to its own.
struct ShadingScene {
  const std::vector<Material>& materials;
  const std::vector<Light>& lights;

  ShadingScene(const Scene& s) : materials(s.materials), lights(s.lights) {}  // implicit: a Scene shades as itself
  ShadingScene(const std::vector<Material>& m, const std::vector<Light>& l) : materials(m), lights(l) {}
};

// What the lighting estimators need to know about the render.
struct ShadingContext {
  ShadingScene scene;
  const Intersector& geometry;
  int light_samples = 1;        // -l: samples per area (non-delta) light
  bool hemisphere = false;      // -H: estimate direct light by hemisphere sampling
  bool course_area_pdf = false; // reproduce the course's area-light pdf (see docs/differences.md)
};

// Light emitted by the surface `hit` toward the ray's origin (emission is
// seen from both sides).
Color zero_bounce_radiance(const ShadingContext& ctx, const Ray& r, const Hit& hit);

// Direct light at `hit` by sampling directions uniformly over the
// hemisphere around the normal: lights.size() * light_samples samples, each
// collecting the emission of whatever it hits (or the ambient sky it
// escapes to), weighted by f cos / pdf.
Color estimate_direct_lighting_hemisphere(const ShadingContext& ctx, const Ray& r, const Hit& hit, Rng& rng);

// Direct light at `hit` by sampling the lights: light_samples samples per
// non-delta light and one per delta light, skipping samples below the
// surface and occluded ones (shadow rays from the hit point, min_t = eps,
// max_t = distance - eps), each weighted by f cos / pdf, averaged per light
// and summed over the lights.
Color estimate_direct_lighting_importance(const ShadingContext& ctx, const Ray& r, const Hit& hit, Rng& rng);

// One bounce: the estimator chosen by -H.
Color one_bounce_radiance(const ShadingContext& ctx, const Ray& r, const Hit& hit, Rng& rng);

// What --part 3 renders: emission seen directly plus one bounce of direct
// light; rays that escape see the ambient sky.
Color direct_illumination(const ShadingContext& ctx, const Ray& r, Rng& rng);

}  // namespace pt
