// The path inspector: replays one sample of one pixel through the build's
// own pixel function, radiance function and random numbers, and records
// what happens along its path.
//
// How it observes (see README.md): the geometry is wrapped, so every ray
// query is seen; the random numbers drawn between two events are found by
// stepping a copy of the sample's generator until it matches the live one;
// the light and BSDF samples are sample_light and bsdf_sample_f evaluated
// again on those numbers and matched to the shadow and bounce rays; the
// given code's hooks (common/path_recorder.h) report each bounce's
// direct-light estimate and the zero bounce. Nothing here is inside a student's function, so a student's build
// is observed the same way. The path weight and each step's radiance are
// then computed from what was observed with the parts' contracts; on the
// reference code their sum is bit for bit what the render loop adds.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <set>

#include "stages/part5_adaptive_sampling/adaptive_sampling.h"
#include "stages/part1_raytracing/brute_force.h"
#include "common/bsdf.h"
#include "stages/part2_bvh/bvh.h"
#include "viewer/debugger/debugger.h"
#include "common/frame.h"
#include "stages/part4_global_illumination/global_illumination.h"
#include "viewer/debugger/json_values.h"
#include "common/path_recorder.h"
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

// More draws than this between two events: the generator was replaced
// (copied, reseeded), and counting starts again from its new state.
constexpr int kMaxDrawsBetweenEvents = 1 << 16;

class Recorder final : public PathRecorder {
 public:
  Recorder(const Scene& scene, const RenderOptions& opts, PathRecord& rec) : scene_(scene), opts_(opts), rec_(rec) {
    // The light samples the estimator takes at a hit, in the contract's
    // order: -l per area (non-delta) light, one per delta light.
    for (size_t i = 0; i < scene.lights.size(); ++i)
      expected_lights_.insert(expected_lights_.end(), scene.lights[i].is_delta() ? 1 : size_t(opts.light_samples),
                              int(i));
  }

  bool recording() const { return recording_; }
  bool finished() const { return finished_; }
  bool in_query = false;  // inside a call to the wrapped geometry

  void start(const Ray& camera_ray, const Rng& rng) {
    recording_ = true;
    live_ = &rng;
    mirror_ = rng;
    rec_.camera_ray = camera_ray;
  }

  void finish(const Color& L) {
    sync();
    if (!rec_.steps.empty()) {
      PathStep& step = rec_.steps.back();
      // Two numbers at the end may be a BSDF sample that carried nothing
      // (f = 0, as on an emitter, or pdf = 0): no bounce ray followed.
      if (pending_.size() >= 2 && !step.bsdf_sampled && step.direct_estimated) {
        PathStep probe = step;
        if (match_bsdf_sample(probe, nullptr) && (!(probe.bsdf_pdf > 0) || is_black(probe.bsdf_f))) {
          step = probe;
          pending_.resize(pending_.size() - 2);
        }
      }
      append_draws(step);
    }
    pending_.clear();
    rec_.returned = L;
    recording_ = false;
    finished_ = true;
  }

  // Which function was running, for the message when one throws.
  std::string where() const {
    if (!recording_) return opts_.part >= 5 ? "raytrace_pixel_adaptive" : "raytrace_pixel";
    if (in_query) return "the closest-hit or shadow query (the BVH, or part 1's intersect_triangle / intersect_sphere)";
    if (in_direct_)
      return opts_.hemisphere_sampling ? "estimate_direct_lighting_hemisphere" : "estimate_direct_lighting_importance";
    if (opts_.part <= 2) return "normal shading";
    if (opts_.part == 3) return "direct_illumination (zero_bounce_radiance)";
    return rec_.steps.empty() ? "est_radiance_global_illumination (zero_bounce_radiance)"
                              : "at_least_one_bounce_radiance";
  }

  void on_intersect(const Ray& ray, bool hit, const Hit& h) {
    if (!recording_) return;
    sync();
    if (in_direct_ && !rec_.steps.empty()) {
      PathStep& step = rec_.steps.back();
      if (!opts_.hemisphere_sampling) {
        // A shadow ray traced as a closest-hit query.
        on_shadow_ray(step, ray, hit);
        return;
      }
      pending_.clear();  // the probe's direction
      HemisphereProbe p;
      p.ray = ray;
      p.hit = hit;
      p.probe_hit = h;
      p.radiance = hit ? emission(material(h.material)) : escaped_radiance(scene_.lights, ray.d);
      p.cos_theta = dot(step.hit.n, normalize(ray.d));
      step.hemisphere_samples.push_back(p);
      return;
    }
    if (!camera_traced_) {
      camera_traced_ = true;
      rec_.camera_hit = hit;
      if (hit) push_step(ray, h, 1);
      return;
    }
    if (rec_.steps.empty()) return;
    PathStep& step = rec_.steps.back();
    // A bounce ray: the last two numbers drawn are its BSDF sample, any
    // before them (after the direct estimate) the Russian-roulette draw.
    if (match_bsdf_sample(step, &ray))
      pending_.resize(pending_.size() - 2);
    else
      rec_.notes.push_back("bounce " + std::to_string(step.bounce + 1) +
                           ": the ray's direction is not bsdf_sample_f's direction for the two numbers drawn "
                           "before it (turned to world space with Frame::from_normal of the hit normal)");
    append_draws(step);
    step.next_traced = true;
    step.next_ray = ray;
    step.next_hit = hit;
    if (hit) push_step(ray, h, step.bounce + 1);
  }

  void on_occluded(const Ray& ray, bool blocked) {
    if (!recording_ || rec_.steps.empty()) return;
    sync();
    PathStep& step = rec_.steps.back();
    if (in_direct_ && !opts_.hemisphere_sampling)
      on_shadow_ray(step, ray, blocked);
    else
      step.other_shadow_rays.push_back(ray);
  }

  void on_direct_begin(const Ray&, const Hit&) override {
    if (!recording_ || rec_.steps.empty()) return;
    sync();
    PathStep& step = rec_.steps.back();
    append_draws(step);
    step.direct_estimated = true;
    step.estimator = opts_.hemisphere_sampling ? "hemisphere sampling" : "light sampling";
    light_cursor_ = 0;
    in_direct_ = true;
  }

  void on_direct_end(const Color& L) override {
    if (!recording_ || rec_.steps.empty()) return;
    sync();
    PathStep& step = rec_.steps.back();
    if (!opts_.hemisphere_sampling) untraced_light_samples(step, pending_.size());
    pending_.clear();
    step.direct = L;
    in_direct_ = false;
  }

  void on_zero_bounce(const Color& L) override {
    if (recording_) rec_.zero_bounce = L;
  }

  void on_todo(const char* what) override {
    if (todos_seen_.insert(what).second) rec_.todos.push_back(std::string("TODO: implement ") + what);
  }

 private:

  // Steps the mirror generator to the live one, keeping the numbers drawn.
  void sync() {
    if (!live_) return;
    for (int n = 0; mirror_ != *live_; ++n) {
      if (n == kMaxDrawsBetweenEvents) {
        mirror_ = *live_;
        if (!lost_track_) rec_.notes.push_back("the sample's random numbers could not be followed (a copied generator?)");
        lost_track_ = true;
        pending_.clear();
        return;
      }
      pending_.push_back(mirror_.uniform());
    }
  }

  void append_draws(PathStep& step) {
    step.roulette_draws.insert(step.roulette_draws.end(), pending_.begin(), pending_.end());
    pending_.clear();
  }

  // The two numbers drawn last, in the order a call received them: a
  // call's arguments may be evaluated right to left, and which order a
  // call site uses is learnt from the first sample matched.
  bool last_two(bool reversed, float* u1, float* u2) const {
    if (pending_.size() < 2) return false;
    const float a = pending_[pending_.size() - 2], b = pending_.back();
    *u1 = reversed ? b : a;
    *u2 = reversed ? a : b;
    return true;
  }
  static std::vector<bool> orders(int known) {
    if (known == 0) return {false};
    if (known == 1) return {true};
    return {false, true};
  }

  // Re-evaluates bsdf_sample_f on the last two numbers drawn; with `ray`,
  // only a sample whose world direction is the ray's counts.
  bool match_bsdf_sample(PathStep& step, const Ray* ray) {
    const Frame frame = Frame::from_normal(step.hit.n);
    const Vec3 wo = frame.to_local(-step.ray.d);
    for (bool reversed : orders(bsdf_order_)) {
      float u1, u2;
      if (!last_two(reversed, &u1, &u2)) return false;
      Vec3 wi;
      float pdf = 0;
      const Color f = bsdf_sample_f(material(step.hit.material), wo, u1, u2, &wi, &pdf);
      const Vec3 world = frame.to_world(wi);
      if (ray && !same_bits(world, ray->d)) continue;
      if (ray) bsdf_order_ = reversed ? 1 : 0;
      step.bsdf_sampled = true;
      step.bsdf_u1 = u1;
      step.bsdf_u2 = u2;
      step.bsdf_wi_local = wi;
      step.bsdf_wi = world;
      step.bsdf_f = f;
      step.bsdf_pdf = pdf;
      step.bsdf_cos_theta = wi.z;
      return true;
    }
    return false;
  }

  LightSampleStep light_sample(const PathStep& step, int light, const Vec3& p, float u1, float u2) const {
    LightSampleStep ls;
    ls.light = light;
    ls.u1 = u1;
    ls.u2 = u2;
    ls.sample = sample_light(scene_.lights[size_t(light)], p, u1, u2);
    const Frame local = Frame::from_normal(step.hit.n);
    const Vec3 wi_local = local.to_local(ls.sample.wi);
    ls.cos_theta = wi_local.z;
    ls.bsdf = bsdf_f(material(step.hit.material), local.to_local(-step.ray.d), wi_local);
    ls.verdict = is_black(ls.sample.radiance) ? "no light (the back of the light)"
                 : ls.cos_theta <= 0          ? "below the surface"
                                              : "not traced";
    return ls;
  }

  // Pairs of numbers drawn in the estimate without a shadow ray after them
  // (the first `count` pending numbers): samples skipped below the surface
  // or with zero pdf, taken to be the contract's next lights.
  void untraced_light_samples(PathStep& step, size_t count) {
    const bool reversed = light_order_ == 1;
    for (size_t i = 0; i + 1 < count; i += 2) {
      if (light_cursor_ >= expected_lights_.size()) break;
      const float a = pending_[i], b = pending_[i + 1];
      step.light_samples.push_back(
          light_sample(step, expected_lights_[light_cursor_++], step.point, reversed ? b : a, reversed ? a : b));
    }
  }

  // A shadow ray of the light-sampling estimate: find the light sample
  // (light, numbers) whose direction it follows.
  void on_shadow_ray(PathStep& step, const Ray& ray, bool blocked) {
    const size_t before = pending_.size() >= 2 ? pending_.size() - 2 : pending_.size();
    // The contract's next light first, then every light; sampled from the
    // ray's origin, or from the hit point when the code moved the shadow
    // ray's origin off the surface.
    std::vector<int> candidates(expected_lights_.begin() + long(std::min(light_cursor_, expected_lights_.size())),
                                expected_lights_.end());
    for (size_t i = 0; i < scene_.lights.size(); ++i) candidates.push_back(int(i));
    for (bool reversed : orders(light_order_)) {
      float u1, u2;
      if (!last_two(reversed, &u1, &u2)) break;
      for (int light : candidates)
        for (const Vec3& p : {ray.o, step.point}) {
          LightSampleStep ls = light_sample(step, light, p, u1, u2);
          if (!same_bits(ls.sample.wi, ray.d)) continue;
          // A delta light ignores its numbers: only other lights tell the order.
          if (!scene_.lights[size_t(light)].is_delta()) light_order_ = reversed ? 1 : 0;
          untraced_light_samples(step, before);
          // Follow the contract's order from this light on.
          for (size_t k = light_cursor_; k < expected_lights_.size(); ++k)
            if (expected_lights_[k] == light) {
              light_cursor_ = k + 1;
              break;
            }
          set_shadow(ls, ray, blocked);
          step.light_samples.push_back(ls);
          pending_.clear();
          return;
        }
    }
    step.other_shadow_rays.push_back(ray);
  }

  static void set_shadow(LightSampleStep& ls, const Ray& ray, bool blocked) {
    ls.shadow_traced = true;
    ls.shadow_ray = ray;
    ls.blocked = blocked;
    ls.verdict = blocked ? "blocked" : "lit";
    if (!blocked && ls.sample.pdf > 0 && ls.cos_theta > 0)
      ls.contribution = ls.bsdf * ls.sample.radiance * (ls.cos_theta / ls.sample.pdf);
  }

  const Material& material(int index) const {
    static const Material fallback;
    return index >= 0 && size_t(index) < scene_.materials.size() ? scene_.materials[size_t(index)] : fallback;
  }

  void push_step(const Ray& ray, const Hit& h, int bounce) {
    PathStep s;
    s.bounce = bounce;
    s.ray = ray;
    s.hit = h;
    s.point = ray.at(h.t);
    const Material& m = material(h.material);
    s.material = (m.name.empty() ? "material " + std::to_string(h.material) : m.name) + " (" + to_string(m.type) + ")";
    s.emission = emission(m);
    rec_.steps.push_back(s);
  }

  const Scene& scene_;
  const RenderOptions& opts_;
  PathRecord& rec_;
  bool recording_ = false, finished_ = false, camera_traced_ = false, in_direct_ = false, lost_track_ = false;
  const Rng* live_ = nullptr;
  Rng mirror_;
  std::vector<float> pending_;  // numbers drawn since the last event
  std::vector<int> expected_lights_;
  size_t light_cursor_ = 0;
  // The order in which this build's calls of sample_light and of
  // bsdf_sample_f received their two numbers: -1 not known yet, 0 left to
  // right, 1 right to left.
  int light_order_ = -1, bsdf_order_ = -1;
  std::set<std::string> todos_seen_;
};

// The geometry the recorded sample traces against: the build's own,
// watched.
class RecordingIntersector final : public Intersector {
 public:
  RecordingIntersector(const Intersector& inner, Recorder& rec) : inner_(inner), rec_(rec) {}

  bool intersect(Ray& r, Hit* hit) const override {
    if (!rec_.recording()) return inner_.intersect(r, hit);
    const Ray before = r;
    Hit local;
    rec_.in_query = true;
    const bool found = inner_.intersect(r, hit ? hit : &local);
    rec_.in_query = false;
    rec_.on_intersect(before, found, hit ? *hit : local);
    return found;
  }

  bool occluded(const Ray& r) const override {
    if (!rec_.recording()) return inner_.occluded(r);
    rec_.in_query = true;
    const bool blocked = inner_.occluded(r);
    rec_.in_query = false;
    rec_.on_occluded(r, blocked);
    return blocked;
  }

 private:
  const Intersector& inner_;
  Recorder& rec_;
};

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
// contracts of parts 3 and 4; then their sum.
void account(const RenderOptions& opts, PathRecord& rec) {
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
    if (step.bsdf_sampled && step.next_hit) {
      const float cos_over_pdf = step.bsdf_wi_local.z / (step.bsdf_pdf * step.continue_probability);
      throughput *= step.bsdf_f * cos_over_pdf;
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

  Recorder recorder(scene, opts, rec);
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
    account(opts, rec);
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
  return rec;
}

// ---------------------------------------------------------------- JSON

Json LightSampleStep::json() const {
  Json o = json_object();
  o.set("light", json_int(light))
      .set("u", json_pair(u1, u2))
      .set("wi", json_vec(sample.wi))
      .set("distance", json_float(sample.distance))
      .set("pdf", json_float(sample.pdf))
      .set("radiance", json_vec(sample.radiance))
      .set("cos_theta", json_float(cos_theta))
      .set("bsdf", json_vec(bsdf))
      .set("verdict", json_text(verdict))
      .set("shadow_traced", json_bool(shadow_traced));
  if (shadow_traced) o.set("shadow_ray", json_ray(shadow_ray)).set("blocked", json_bool(blocked));
  o.set("contribution", json_vec(contribution));
  return o;
}

Json HemisphereProbe::json() const {
  Json o = json_object();
  o.set("ray", json_ray(ray)).set("hit", json_bool(hit));
  if (hit)
    o.set("t", json_float(probe_hit.t))
        .set("point", json_vec(ray.at(probe_hit.t)))
        .set("material", json_int(probe_hit.material));
  o.set("radiance", json_vec(radiance)).set("cos_theta", json_float(cos_theta));
  return o;
}

Json PathStep::json() const {
  Json o = json_object();
  o.set("bounce", json_int(bounce)).set("depth", json_int(depth)).set("ray", json_ray(ray));
  o.set("t", json_float(hit.t))
      .set("point", json_vec(point))
      .set("normal", json_vec(hit.n))
      .set("material_index", json_int(hit.material));
  o.set("primitive", json_int(hit.primitive))
      .set("material", json_text(material))
      .set("emission", json_vec(emission));
  o.set("direct_estimated", json_bool(direct_estimated));
  if (direct_estimated) {
    std::vector<Json> ls, hs, other;
    for (const LightSampleStep& s : light_samples) ls.push_back(s.json());
    for (const HemisphereProbe& p : hemisphere_samples) hs.push_back(p.json());
    for (const Ray& r : other_shadow_rays) other.push_back(json_ray(r));
    o.set("estimator", json_text(estimator))
        .set("direct", json_vec(direct))
        .set("direct_counted", json_bool(direct_counted));
    o.set("light_samples", json_list(std::move(ls))).set("hemisphere_samples", json_list(std::move(hs)));
    if (!other.empty()) o.set("other_shadow_rays", json_list(std::move(other)));
  }
  o.set("path_weight", json_vec(path_weight)).set("radiance_added", json_vec(radiance_added));
  std::vector<Json> draws;
  for (float u : roulette_draws) draws.push_back(json_float(u));
  o.set("roulette", json_object(true)
                        .set("applies", json_bool(roulette_applies))
                        .set("continue_probability", json_float(continue_probability))
                        .set("draws", json_array(std::move(draws), true)));
  o.set("bsdf_sampled", json_bool(bsdf_sampled));
  if (bsdf_sampled)
    o.set("bsdf_sample", json_object()
                             .set("u", json_pair(bsdf_u1, bsdf_u2))
                             .set("wi_local", json_vec(bsdf_wi_local))
                             .set("wi", json_vec(bsdf_wi))
                             .set("f", json_vec(bsdf_f))
                             .set("pdf", json_float(bsdf_pdf))
                             .set("cos_theta", json_float(bsdf_cos_theta)));
  o.set("next_traced", json_bool(next_traced));
  if (next_traced) o.set("next_ray", json_ray(next_ray)).set("next_hit", json_bool(next_hit));
  return o;
}

Json PathRecord::json() const {
  std::vector<Json> steps_json, segments;
  // Each segment on one line: a path with many light samples has many.
  const auto segment = [&](const char* kind, const Vec3& from, const Vec3& to, int bounce) {
    segments.push_back(json_object(true)
                           .set("kind", json_text(kind))
                           .set("from", json_vec(from))
                           .set("to", json_vec(to))
                           .set("bounce", json_int(bounce)));
  };
  const auto open_segment = [&](const char* kind, const Ray& r, int bounce) {
    segments.push_back(json_object(true)
                           .set("kind", json_text(kind))
                           .set("from", json_vec(r.o))
                           .set("direction", json_vec(r.d))
                           .set("bounce", json_int(bounce)));
  };
  if (error.empty() || !steps.empty()) {
    if (camera_hit && !steps.empty())
      segment("camera", camera_ray.o, steps.front().point, 1);
    else
      open_segment("camera", camera_ray, 1);
  }
  for (const PathStep& s : steps) {
    steps_json.push_back(s.json());
    for (const LightSampleStep& l : s.light_samples)
      if (l.shadow_traced) segment(l.blocked ? "shadow_blocked" : "shadow", l.shadow_ray.o,
                                   l.shadow_ray.at(l.shadow_ray.max_t), s.bounce);
    for (const HemisphereProbe& p : s.hemisphere_samples) {
      if (p.hit)
        segment("probe", p.ray.o, p.ray.at(p.probe_hit.t), s.bounce);
      else
        open_segment("probe", p.ray, s.bounce);
    }
    if (s.next_traced && !s.next_hit) open_segment("bounce", s.next_ray, s.bounce + 1);
  }
  for (size_t i = 1; i < steps.size(); ++i) segment("bounce", steps[i - 1].point, steps[i].point, steps[i].bounce);
  Json o = json_object();
  o.set("part", json_int(part)).set("pixel", json_array({json_int(x), json_int(y)}, true));
  o.set("sample", json_int(sample)).set("seed", json_seed(seed)).set("samples_per_pixel", json_int(samples_per_pixel));
  o.set("samples_taken", json_int(samples_taken))
      .set("camera_ray", json_ray(camera_ray))
      .set("camera_hit", json_bool(camera_hit));
  o.set("zero_bounce", json_vec(zero_bounce)).set("steps", json_list(std::move(steps_json))).set("end", json_text(end));
  o.set("returned", json_vec(returned)).set("sum_of_contributions", json_vec(sum_of_contributions));
  o.set("exact", json_bool(exact)).set("agrees", json_bool(agrees)).set("segments", json_list(std::move(segments)));
  o.set("notes", json_strings(notes)).set("todos", json_strings(todos));
  if (!error.empty()) o.set("error", json_text(error));
  return o;
}

}  // namespace pt::debug
