#include "viewer/debugger/recorder.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>

#include "common/bsdf.h"
#include "common/frame.h"
#include "common/lights.h"
#include "stages/part3_direct_lighting/direct_lighting.h"

namespace pt::debug {

namespace {

bool same_bits(const Vec3& a, const Vec3& b) {
  const float x[3] = {a.x, a.y, a.z}, y[3] = {b.x, b.y, b.z};
  return std::memcmp(x, y, sizeof x) == 0;
}

// More draws than this between two events: the generator was replaced
// (copied, reseeded), and counting starts again from its new state.
constexpr int kMaxDrawsBetweenEvents = 1 << 16;

}  // namespace

void Recorder::start(const Ray& camera_ray, const Rng& rng) {
  recording_ = true;
  live_ = &rng;
  mirror_ = rng;
  rec_.camera_ray = camera_ray;
}

void Recorder::finish(const Color& L) {
  sync();
  if (!rec_.steps.empty()) {
    PathStep& step = rec_.steps.back();
    // Two numbers at the end may be a BSDF sample that carried nothing
    // (f = 0, as on an emitter, or pdf = 0, as a refraction at total
    // internal reflection): no bounce ray followed.
    if (pending_.size() >= 2 && !step.bsdf_sampled && (step.direct_estimated || step.delta)) {
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

std::string Recorder::where() const {
  if (!recording_) return opts_.part >= 5 ? "raytrace_pixel_adaptive" : "raytrace_pixel";
  if (in_query) return "the closest-hit or shadow query (the BVH, or part 1's intersect_triangle / intersect_sphere)";
  if (in_direct_)
    return opts_.hemisphere_sampling ? "estimate_direct_lighting_hemisphere" : "estimate_direct_lighting_importance";
  if (opts_.part <= 2) return "normal shading";
  if (opts_.part == 3) return "direct_illumination (zero_bounce_radiance)";
  return rec_.steps.empty() ? "est_radiance_global_illumination (zero_bounce_radiance)" : "at_least_one_bounce_radiance";
}

void Recorder::on_intersect(const Ray& ray, bool hit, const Hit& h) {
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

void Recorder::on_occluded(const Ray& ray, bool blocked) {
  if (!recording_ || rec_.steps.empty()) return;
  sync();
  PathStep& step = rec_.steps.back();
  if (in_direct_ && !opts_.hemisphere_sampling)
    on_shadow_ray(step, ray, blocked);
  else
    step.other_shadow_rays.push_back(ray);
}

void Recorder::on_direct_begin(const Ray&, const Hit&) {
  if (!recording_ || rec_.steps.empty()) return;
  sync();
  PathStep& step = rec_.steps.back();
  append_draws(step);
  step.direct_estimated = true;
  step.estimator = opts_.hemisphere_sampling ? "hemisphere sampling" : "light sampling";
  in_direct_ = true;
}

void Recorder::on_direct_end(const Color& L) {
  if (!recording_ || rec_.steps.empty()) return;
  sync();
  pending_.clear();  // the estimate's own numbers
  rec_.steps.back().direct = L;
  in_direct_ = false;
}

void Recorder::on_zero_bounce(const Color& L) {
  if (recording_) rec_.zero_bounce = L;
}

void Recorder::on_todo(const char* what) {
  if (todos_seen_.insert(what).second) rec_.todos.push_back(std::string("TODO: implement ") + what);
}

void Recorder::on_light_sample(const Light& light, const Vec3&, float u1, float u2, const LightSample& s) {
  if (!recording_ || !in_direct_ || rec_.steps.empty()) return;
  sync();
  take(u1, u2);
  PathStep& step = rec_.steps.back();
  LightSampleStep ls;
  ls.light = light_index(light);
  ls.u1 = u1;
  ls.u2 = u2;
  ls.sample = s;
  const Frame local = Frame::from_normal(step.hit.n);
  const Vec3 wi_local = local.to_local(s.wi);
  ls.cos_theta = wi_local.z;
  ls.bsdf = bsdf_f(material(step.hit.material), local.to_local(-step.ray.d), wi_local);
  // Until a shadow ray follows it: what the contract says of a sample
  // that gets none.
  const bool too_close = std::isfinite(s.distance) && !(s.distance - kRayEpsilon > kRayEpsilon);
  ls.verdict = is_black(s.radiance)  ? "no light (the back of the light)"
               : ls.cos_theta <= 0 ? "below the surface"
               : too_close         ? "at the surface (shorter than the ray epsilon)"
                                   : "not traced";
  step.light_samples.push_back(ls);
}

// Steps the mirror generator to the live one, keeping the numbers drawn.
void Recorder::sync() {
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

void Recorder::append_draws(PathStep& step) {
  step.roulette_draws.insert(step.roulette_draws.end(), pending_.begin(), pending_.end());
  pending_.clear();
}

void Recorder::take(float u1, float u2) {
  for (float u : {u1, u2}) {
    const auto it = std::find_if(pending_.rbegin(), pending_.rend(), [&](float x) { return std::memcmp(&x, &u, 4) == 0; });
    if (it != pending_.rend()) pending_.erase(std::next(it).base());
  }
}

bool Recorder::match_bsdf_sample(PathStep& step, const Ray* ray) {
  if (pending_.size() < 2) return false;
  const Frame frame = Frame::from_normal(step.hit.n);
  const Vec3 wo = frame.to_local(-step.ray.d);
  const float a = pending_[pending_.size() - 2], b = pending_.back();
  const Material& m = material(step.hit.material);
  const auto direction = [&](int reversed, Vec3* wi, float* pdf) {
    const Color f = bsdf_sample_f(m, wo, reversed ? b : a, reversed ? a : b, wi, pdf);
    return std::make_pair(f, frame.to_world(*wi));
  };
  for (int reversed : {0, 1}) {
    if (bsdf_order_ >= 0 && reversed != bsdf_order_) continue;
    if (bsdf_order_ < 0 && !ray && reversed) break;  // no ray to tell the order by: as drawn
    const float u1 = reversed ? b : a, u2 = reversed ? a : b;
    Vec3 wi;
    float pdf = 0;
    const auto [f, world] = direction(reversed, &wi, &pdf);
    if (ray && !same_bits(world, ray->d)) continue;
    // The order is learnt only from a sample it decides: a mirror's
    // direction (which takes no number) or a glass's choice that both
    // orders make alike tells nothing.
    if (ray && bsdf_order_ < 0) {
      Vec3 other_wi;
      float other_pdf = 0;
      if (!same_bits(direction(1 - reversed, &other_wi, &other_pdf).second, ray->d)) bsdf_order_ = reversed;
    }
    step.bsdf_sampled = true;
    step.bsdf_wo_local = wo;
    step.bsdf_scatter = (wi.z > 0) == (wo.z > 0) ? "reflected" : "refracted";
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

// A shadow ray of the light-sampling estimate: it tests the latest light
// sample not yet tested whose direction it follows.
void Recorder::on_shadow_ray(PathStep& step, const Ray& ray, bool blocked) {
  for (auto it = step.light_samples.rbegin(); it != step.light_samples.rend(); ++it) {
    LightSampleStep& ls = *it;
    if (ls.shadow_traced || !same_bits(ls.sample.wi, ray.d)) continue;
    ls.shadow_traced = true;
    ls.shadow_ray = ray;
    ls.blocked = blocked;
    ls.verdict = blocked ? "blocked" : "lit";
    if (!blocked && !is_black(ls.sample.radiance) && ls.cos_theta > 0)
      ls.contribution = ls.bsdf * ls.sample.radiance * (ls.cos_theta / ls.sample.pdf);
    return;
  }
  step.other_shadow_rays.push_back(ray);
}

// The light's index in the scene: the build passes the scene's own lights,
// or a copy of one (found by what it is).
int Recorder::light_index(const Light& light) const {
  const std::vector<Light>& all = scene_.lights;
  if (!all.empty() && &light >= all.data() && &light < all.data() + all.size()) return int(&light - all.data());
  for (size_t i = 0; i < all.size(); ++i) {
    const Light& l = all[i];
    if (l.type == light.type && same_bits(l.position, light.position) && same_bits(l.direction, light.direction) &&
        same_bits(l.dim_x, light.dim_x) && same_bits(l.dim_y, light.dim_y) && same_bits(l.radiance, light.radiance))
      return int(i);
  }
  return -1;
}

const Material& Recorder::material(int index) const {
  static const Material fallback;
  return index >= 0 && size_t(index) < materials_.size() ? materials_[size_t(index)] : fallback;
}

void Recorder::push_step(const Ray& ray, const Hit& h, int bounce) {
  PathStep s;
  s.bounce = bounce;
  s.ray = ray;
  s.hit = h;
  s.point = ray.at(h.t);
  const Material& m = material(h.material);
  s.material = (m.name.empty() ? "material " + std::to_string(h.material) : m.name) + " (" + to_string(m.type) + ")";
  s.bsdf_model = bsdf_model(m).name;
  s.delta = bsdf_is_delta(m);
  s.emission = emission(m);
  rec_.steps.push_back(s);
}

bool RecordingIntersector::intersect(Ray& r, Hit* hit) const {
  if (!rec_.recording()) return inner_.intersect(r, hit);
  const Ray before = r;
  Hit local;
  rec_.in_query = true;
  const bool found = inner_.intersect(r, hit ? hit : &local);
  rec_.in_query = false;
  rec_.on_intersect(before, found, hit ? *hit : local);
  return found;
}

bool RecordingIntersector::occluded(const Ray& r) const {
  if (!rec_.recording()) return inner_.occluded(r);
  rec_.in_query = true;
  const bool blocked = inner_.occluded(r);
  rec_.in_query = false;
  rec_.on_occluded(r, blocked);
  return blocked;
}

}  // namespace pt::debug
