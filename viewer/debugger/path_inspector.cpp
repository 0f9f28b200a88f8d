// The path inspector: replays one sample of one pixel through the build's
// own pixel function, radiance function and random numbers, with the
// recorder (recorder.h) listening, then accounts for the path: the path
// weight and each step's radiance computed from what was recorded with the
// parts' contracts; on the reference code their sum is bit for bit what
// the render loop adds. The JSON of the results: path_json.cpp.
#include <cmath>
#include <cstring>

#include "stages/part5_adaptive_sampling/adaptive_sampling.h"
#include "stages/part1_raytracing/brute_force.h"
#include "stages/part2_bvh/bvh.h"
#include "viewer/debugger/debugger.h"
#include "viewer/debugger/recorder.h"
#include "common/lights.h"
#include "stages/part4_global_illumination/global_illumination.h"
#include "stages/part1_raytracing/pixel_sampling.h"
#include "pathtracer/radiance.h"

namespace pt::debug {

namespace {

bool same_bits(const Color& a, const Color& b) {
  const float x[3] = {a.x, a.y, a.z}, y[3] = {b.x, b.y, b.z};
  return std::memcmp(x, y, sizeof x) == 0;
}

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Equal but for float rounding: relative 1e-5 in every channel.
bool close(const Color& a, const Color& b) {
  const float x[3] = {a.x, a.y, a.z}, y[3] = {b.x, b.y, b.z};
  for (int i = 0; i < 3; ++i)
    if (!(std::fabs(x[i] - y[i]) <= 1e-5f * std::fmax(std::fabs(x[i]), std::fabs(y[i]))) && !same_bits(x[i], y[i]))
      return false;
  return true;
}

void check_options(const Scene& scene, const RenderOptions& opts, int x, int y, int sample_index) {
  if (opts.part < 1 || opts.part > kPartsBuilt)
    throw InputError("part must be from 1 to " + std::to_string(kPartsBuilt));
  const Camera& cam = scene.camera;
  if (cam.width != opts.width || cam.height != opts.height)
    throw InputError("the camera is " + std::to_string(cam.width) + "x" + std::to_string(cam.height) +
                     " but the options say " + std::to_string(opts.width) + "x" + std::to_string(opts.height) +
                     ": configure it with configure_camera first");
  if (x < 0 || x >= cam.width || y < 0 || y >= cam.height)
    throw InputError("pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") is outside the " +
                     std::to_string(cam.width) + "x" + std::to_string(cam.height) + " image");
  if (opts.samples_per_pixel < 1) throw InputError("samples per pixel (-s) must be at least 1");
  if (sample_index < 0 || sample_index >= opts.samples_per_pixel)
    throw InputError("sample index " + std::to_string(sample_index) + " is out of range: -s " +
                     std::to_string(opts.samples_per_pixel) + " takes samples 0 to " +
                     std::to_string(opts.samples_per_pixel - 1));
  if (opts.light_samples < 1) throw InputError("samples per light (-l) must be at least 1");
  if (opts.max_depth < 0) throw InputError("the maximum ray depth (-m) must not be negative");
  if (opts.part >= 5 && opts.adaptive_batch < 1) throw InputError("the adaptive batch size (-a B) must be at least 1");
  if (opts.part >= 5 && !(opts.adaptive_tolerance >= 0) )
    throw InputError("the adaptive tolerance (-a B T) must be a number of at least 0");
}

// Each step's path weight and radiance, from what was observed, by the
// contracts of parts 3, 4 and 6 (a delta BSDF's light is what its bounce
// reaches); then their sum, in the estimator's order.
void account(const RenderOptions& opts, const std::vector<Light>& lights, PathRecord& rec) {
  if (opts.part <= 2) {
    // Normal shading: the colour is the normal at the first hit; nothing
    // is added along a path.
    if (!rec.steps.empty()) rec.steps.front().radiance_added = rec.returned;
    rec.sum_of_contributions = rec.returned;
    rec.notes.push_back("parts 1 and 2 render normal shading: the colour is n/2 + 1/2 at the first hit");
    return;
  }
  const PathOptions path = path_options(opts);
  Color throughput(1.0f), bounces(0.0f);
  for (size_t k = 0; k < rec.steps.size(); ++k) {
    PathStep& step = rec.steps[k];
    const bool first = k == 0;
    step.depth = opts.part >= 4 ? path.max_depth - int(k) : 1;
    step.path_weight = throughput;
    step.roulette_applies = opts.part >= 4 && path.russian_roulette && !first && step.depth > 1;
    step.continue_probability = step.roulette_applies ? kContinueProbability : 1.0f;
    if (step.direct_estimated) {
      step.direct_counted = opts.part == 3 || ((path.accumulate || step.depth == 1) && !(path.skip_direct && first));
      if (step.direct_counted) {
        step.radiance_added = throughput * step.direct;
        bounces += step.radiance_added;
      }
    }
    if (!step.bsdf_sampled || !step.next_traced) continue;
    // |cos theta|: a refracted wi lies below the surface.
    const float cos_over_pdf = std::fabs(step.bsdf_wi_local.z) / (step.bsdf_pdf * step.continue_probability);
    // After a delta bounce, what it reaches is the delta vertex's direct
    // light, counted by the same rule (-o 0: at the last vertex, depth 1,
    // whose bounce is traced for that light only).
    const bool count_reached = opts.part >= 4 && step.delta && (path.accumulate || step.depth == 1) &&
                               !(path.skip_direct && first);
    if (!step.next_hit) {
      step.reached = escaped_radiance(lights, step.next_ray.d);
      if (count_reached) {
        step.reached_counted = true;
        step.radiance_added = throughput * step.bsdf_f * cos_over_pdf * step.reached;
        bounces += step.radiance_added;
      }
      continue;
    }
    throughput *= step.bsdf_f * cos_over_pdf;
    if (step.delta && k + 1 < rec.steps.size()) {
      step.reached = rec.steps[k + 1].emission;
      if (count_reached) {
        step.reached_counted = true;
        step.radiance_added = throughput * step.reached;
        bounces += step.radiance_added;
      }
    }
  }
  rec.sum_of_contributions = rec.zero_bounce + bounces;
}

std::string end_reason(const RenderOptions& opts, const PathRecord& rec) {
  if (!rec.error.empty()) return "stopped by an error";
  if (!rec.camera_hit) return "the camera ray escaped the scene";
  if (opts.part <= 2) return "normal shading stops at the first hit";
  if (opts.part == 3) return "part 3 stops after one bounce of direct light";
  const PathStep& last = rec.steps.back();
  if (path_options(opts).max_depth == 0) return "-m 0: only the light seen directly";
  if (last.depth <= 1) return "the path reached the maximum depth (-m)";
  if (last.next_traced && !last.next_hit) return "the bounce ray escaped the scene";
  if (!last.bsdf_sampled && !last.roulette_draws.empty())
    return "Russian roulette ended the path (draw " + json_number(last.roulette_draws.front()) + " >= " +
           json_number(kContinueProbability) + ")";
  if (last.bsdf_sampled && !last.next_traced) return "the BSDF sample carried nothing (f = 0 or pdf = 0)";
  return "the estimator traced no further";
}

}  // namespace

std::unique_ptr<Intersector> make_geometry(const Scene& scene, const RenderOptions& opts) {
  if (opts.part < 2) return std::make_unique<BruteForceIntersector>(scene);
  BVHOptions bo;
  bo.max_leaf_size = opts.bvh_max_leaf;
  bo.bins = opts.bvh_bins;
  return std::make_unique<BVH>(scene, bo);
}

PathRecord record_path(const Scene& scene, const Intersector& geometry, const RenderOptions& opts, int x, int y,
                       int sample_index) {
  check_options(scene, opts, x, y, sample_index);
  PathRecord rec;
  rec.part = opts.part;
  rec.x = x;
  rec.y = y;
  rec.sample = sample_index;
  rec.seed = opts.seed;
  rec.samples_per_pixel = opts.samples_per_pixel;

  // The materials with the BSDF models of the part (its delta BSDFs, its
  // microfacet), as the radiance function shades them.
  const std::shared_ptr<const PartShading> shading = part_shading(scene, opts.part, opts.bsdf_hemisphere);
  Recorder recorder(scene, shading->materials, opts, rec);
  const RecordingIntersector isect(geometry, recorder);
  // The render's radiance function for the part (pathtracer/radiance.h),
  // on the watched geometry.
  const RadianceFn radiance = part_radiance(scene, isect, opts);

  // The pixel function calls `replay` once per sample, in order. Only the
  // chosen sample is recorded. The others are traced only where their
  // values matter (part 5's stopping rule, which also gives the number of
  // samples the pixel takes); elsewhere they are skipped.
  int calls = 0;
  const RadianceFn replay = [&](const Ray& r, Rng& rng) -> Color {
    const int index = calls++;
    if (index == sample_index) {
      recorder.start(r, rng);
      const Color L = radiance(r, rng);
      recorder.finish(L);
      return L;
    }
    if (opts.part >= 5) return radiance(r, rng);
    return Color(0.0f);
  };

  {
    ScopedPathRecorder install(&recorder);
    try {
      if (opts.part >= 5) {
        AdaptiveOptions adaptive;
        adaptive.batch = opts.adaptive_batch;
        adaptive.tolerance = opts.adaptive_tolerance;
        int taken = 0;
        raytrace_pixel_adaptive(scene.camera, x, y, opts.samples_per_pixel, opts.seed, replay, adaptive, &taken);
        rec.samples_taken = taken;
      } else {
        raytrace_pixel(scene.camera, x, y, opts.samples_per_pixel, opts.seed, replay);
        rec.samples_taken = calls;
      }
    } catch (const std::exception& e) {
      rec.error = recorder.where() + ": " + e.what();
    } catch (...) {
      rec.error = recorder.where() + ": threw something that is not a std::exception";
    }
  }

  if (rec.error.empty() && !recorder.finished()) {
    if (opts.part >= 5 && rec.samples_taken <= sample_index && calls == rec.samples_taken)
      throw InputError("sample " + std::to_string(sample_index) + " was not taken: adaptive sampling stopped pixel (" +
                       std::to_string(x) + ", " + std::to_string(y) + ") after " +
                       std::to_string(rec.samples_taken) + " samples (0 to " +
                       std::to_string(rec.samples_taken - 1) + ")");
    rec.error = std::string(opts.part >= 5 ? "raytrace_pixel_adaptive" : "raytrace_pixel") + " traced " +
                std::to_string(calls) + " sample(s) of this pixel, never sample " + std::to_string(sample_index);
  }
  if (rec.error.empty()) {
    account(opts, shading->lights, rec);
    rec.exact = same_bits(rec.sum_of_contributions, rec.returned);
    rec.agrees = rec.exact || close(rec.sum_of_contributions, rec.returned);
    if (!rec.agrees)
      rec.notes.push_back("the steps' radiance does not add up to what the estimator returned: it computed something "
                          "other than the contracts of parts 3 and 4 describe");
    else if (!rec.exact)
      rec.notes.push_back("the steps' radiance adds up to what the estimator returned within float rounding (it "
                          "groups its sums differently from the reference)");
  }
  rec.end = end_reason(opts, rec);
  if (!rec.todos.empty()) {
    // The path is what the stubs' stand-ins do: say so, by name.
    std::string names;
    for (const std::string& t : rec.todos) {
      // "TODO: implement Part 1: generate_ray (stages/...); note" -> "generate_ray"
      const size_t colon = t.find(": ", t.find("Part "));
      const std::string rest = colon == std::string::npos ? t : t.substr(colon + 2);
      names += (names.empty() ? "" : ", ") + rest.substr(0, rest.find(" ("));
    }
    rec.end += " (" + names + (rec.todos.size() == 1 ? " is" : " are") + (rec.todos.size() == 1 ? " still a stub)" : " still stubs)");
    rec.notes.push_back("the part's functions are still stubs (" + names +
                        "): this path is what their stand-ins do, not what the assignment asks for");
  }
  return rec;
}

}  // namespace pt::debug
