// Recording one path for the path inspector (viewer/debugger).
//
// The inspector watches a replayed sample through the interfaces a part's
// code has to use: it wraps the geometry (every ray query) and follows the
// sample's random numbers. What it cannot see that way, the given code
// reports through the hooks below: each call of sample_light with its
// numbers and result, each bounce's direct-light estimate
// (one_bounce_radiance), the radiance seen directly (the zero bounce) and
// each TODO stub reached. The hooks sit in given code, never in a solution
// region, so a student's build is watched too, and what is shown is what
// the build did. (A BSDF sample is known by its bounce ray, whose
// direction is bsdf_sample_f's for the numbers drawn before it, bit for
// bit: a hook in bsdf_sample_f cost 2 % of a render's time.)
//
// Nothing is recorded unless a PathRecorder is installed on the calling
// thread: a normal render pays one thread-local test per hook (a handful
// per path) and computes exactly the same numbers.
#pragma once
#include "common/ray.h"

namespace pt {

struct Light;
struct LightSample;

// Receives the events of the calling thread while installed. Every method
// does nothing by default.
class PathRecorder {
 public:
  virtual ~PathRecorder() = default;
  // sample_light(light, p, u1, u2) returned `s`.
  virtual void on_light_sample(const Light& /*light*/, const Vec3& /*p*/, float /*u1*/, float /*u2*/,
                               const LightSample& /*s*/) {}

  // one_bounce_radiance at `hit` of `r` begins / returns L.
  virtual void on_direct_begin(const Ray& /*r*/, const Hit& /*hit*/) {}
  virtual void on_direct_end(const Color& /*L*/) {}
  // The radiance a camera ray contributes by itself (emission or sky; zero
  // when the options leave it out).
  virtual void on_zero_bounce(const Color& /*L*/) {}
  virtual void on_todo(const char* /*what*/) {}
};

namespace detail {
inline thread_local PathRecorder* active_recorder = nullptr;
}

// The recorder installed on this thread, or null (normal renders).
inline PathRecorder* active_path_recorder() { return detail::active_recorder; }

// True while a recorder is installed on this thread (never in a normal
// render, hence the branch hint).
inline bool recording_path() { return __builtin_expect(detail::active_recorder != nullptr, 0); }

// Installs a recorder on this thread for the lifetime of the object.
class ScopedPathRecorder {
 public:
  explicit ScopedPathRecorder(PathRecorder* r) : previous_(detail::active_recorder) { detail::active_recorder = r; }
  ~ScopedPathRecorder() { detail::active_recorder = previous_; }
  ScopedPathRecorder(const ScopedPathRecorder&) = delete;
  ScopedPathRecorder& operator=(const ScopedPathRecorder&) = delete;

 private:
  PathRecorder* previous_;
};

namespace detail {
// Out of line (path_recorder.cpp), so that a normal render's code carries
// only the test of recording_path().
[[gnu::cold]] void report_direct_begin(const Ray& r, const Hit& hit);
[[gnu::cold]] void report_direct_end(const Color& L);
[[gnu::cold]] void report_zero_bounce(const Color& L);
[[gnu::cold]] void report_light_sample(const Light& light, const Vec3& p, float u1, float u2, const LightSample& s);
}  // namespace detail

// The hooks the given code calls.
inline void record_direct_begin(const Ray& r, const Hit& hit) {
  if (recording_path()) detail::report_direct_begin(r, hit);
}
// Returns L unchanged.
inline Color record_direct_end(const Color& L) {
  if (recording_path()) detail::report_direct_end(L);
  return L;
}
// Returns L unchanged.
inline Color record_zero_bounce(const Color& L) {
  if (recording_path()) detail::report_zero_bounce(L);
  return L;
}
inline void record_light_sample(const Light& light, const Vec3& p, float u1, float u2, const LightSample& s) {
  if (recording_path()) detail::report_light_sample(light, p, u1, u2, s);
}


}  // namespace pt
