// The path inspector's recorder: while one sample is replayed, it receives
// what the build does (common/path_recorder.h's hooks in the given code,
// and every ray query through RecordingIntersector) and writes it down as
// a PathRecord's steps. Nothing is guessed: each light sample is the call
// of sample_light the build made, with its numbers and result, and a
// shadow ray is matched to the light sample whose direction it follows. The
// random numbers drawn between two events are found by stepping a copy of
// the sample's generator until it equals the live one. A bounce ray's BSDF
// sample is bsdf_sample_f on the two numbers drawn before it, in the order
// that gives the ray's direction bit for bit; the numbers before those are
// the Russian-roulette draws.
#pragma once
#include <set>
#include <string>
#include <vector>

#include "common/intersector.h"
#include "common/path_recorder.h"
#include "common/rng.h"
#include "viewer/debugger/debugger.h"

namespace pt::debug {

class Recorder final : public PathRecorder {
 public:
  // `materials`: the render's, with the BSDF models of its part
  // (pathtracer/radiance.h's part_shading), which the sample was shaded with.
  Recorder(const Scene& scene, const std::vector<Material>& materials, const RenderOptions& opts, PathRecord& rec)
      : scene_(scene), materials_(materials), opts_(opts), rec_(rec) {}

  bool recording() const { return recording_; }
  bool finished() const { return finished_; }
  bool in_query = false;  // inside a call to the wrapped geometry

  // The chosen sample's radiance function starts on `camera_ray` with the
  // sample's generator `rng`, and returns L.
  void start(const Ray& camera_ray, const Rng& rng);
  void finish(const Color& L);

  // Which function was running, for the message when one throws.
  std::string where() const;

  // The wrapped geometry's queries.
  void on_intersect(const Ray& ray, bool hit, const Hit& h);
  void on_occluded(const Ray& ray, bool blocked);

  // The given code's hooks.
  void on_direct_begin(const Ray& r, const Hit& hit) override;
  void on_direct_end(const Color& L) override;
  void on_zero_bounce(const Color& L) override;
  void on_todo(const char* what) override;
  void on_light_sample(const Light& light, const Vec3& p, float u1, float u2, const LightSample& s) override;

 private:
  void sync();
  void append_draws(PathStep& step);
  // Takes the numbers u1 and u2 (the last drawn of each) out of the
  // pending draws: a sampling call received them.
  void take(float u1, float u2);
  void on_shadow_ray(PathStep& step, const Ray& ray, bool blocked);
  // bsdf_sample_f on the last two numbers drawn (in the order learnt from
  // the bounce rays); with `ray`, only a sample whose world direction is
  // the ray's counts.
  bool match_bsdf_sample(PathStep& step, const Ray* ray);
  int light_index(const Light& light) const;
  const Material& material(int index) const;
  void push_step(const Ray& ray, const Hit& h, int bounce);

  const Scene& scene_;
  const std::vector<Material>& materials_;
  const RenderOptions& opts_;
  PathRecord& rec_;
  bool recording_ = false, finished_ = false, camera_traced_ = false, in_direct_ = false, lost_track_ = false;
  const Rng* live_ = nullptr;
  Rng mirror_;
  std::vector<float> pending_;  // numbers drawn since the last event
  // The order in which this build's call of bsdf_sample_f received its two
  // numbers (a call's arguments may be evaluated right to left): -1 not
  // known yet, 0 as drawn, 1 the other way round.
  int bsdf_order_ = -1;
  std::set<std::string> todos_seen_;
};

// The geometry the recorded sample traces against: the build's own,
// watched.
class RecordingIntersector final : public Intersector {
 public:
  RecordingIntersector(const Intersector& inner, Recorder& rec) : inner_(inner), rec_(rec) {}
  bool intersect(Ray& r, Hit* hit) const override;
  bool occluded(const Ray& r) const override;

 private:
  const Intersector& inner_;
  Recorder& rec_;
};

}  // namespace pt::debug
