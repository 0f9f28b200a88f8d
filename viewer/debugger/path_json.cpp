// The path inspector's results as JSON values (json_values.h): a light
// sample, a hemisphere probe, a step, and the whole record with the
// segments the page draws.
#include "viewer/debugger/debugger.h"
#include "viewer/debugger/json_values.h"

namespace pt::debug {

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
      .set("bsdf_model", json_text(bsdf_model))
      .set("delta", json_bool(delta))
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
                             .set("wo_local", json_vec(bsdf_wo_local))
                             .set("wi_local", json_vec(bsdf_wi_local))
                             .set("wi", json_vec(bsdf_wi))
                             .set("f", json_vec(bsdf_f))
                             .set("pdf", json_float(bsdf_pdf))
                             .set("cos_theta", json_float(bsdf_cos_theta))
                             .set("scatter", json_text(bsdf_scatter)));
  if (delta) o.set("reached", json_vec(reached)).set("reached_counted", json_bool(reached_counted));
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
