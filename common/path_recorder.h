// Recording one path for the path inspector (viewer/debugger).
//
// The given code calls these hooks at the points a path's story can be read
// from: each light sample (sample_light), each BSDF sample (bsdf_sample_f),
// each bounce's direct-light estimate (one_bounce_radiance), the radiance
// seen directly (the zero bounce) and each TODO stub reached. Nothing is
// recorded unless a PathRecorder is installed on the calling thread, so a
// normal render only pays one thread-local load per hook and computes
// exactly the same numbers. The hooks sit in given code, never in a
// solution region, so a student's own code is observed too.
#pragma once
#include "ray.h"

namespace pt {

struct Light;
struct LightSample;
struct Material;

// Receives the events of the calling thread while installed. Every method
// does nothing by default.
class PathRecorder {
 public:
  virtual ~PathRecorder() = default;
  virtual void on_light_sample(const Light&, const Vec3& /*p*/, float /*u1*/, float /*u2*/, const LightSample&) {}
  virtual void on_bsdf_sample(const Material&, const Vec3& /*wo*/, float /*u1*/, float /*u2*/, const Vec3& /*wi*/,
                              float /*pdf*/, const Color& /*f*/) {}
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

// One-line hooks for the given code.
inline void record_direct_begin(const Ray& r, const Hit& hit) {
  if (PathRecorder* rec = active_path_recorder()) rec->on_direct_begin(r, hit);
}
inline void record_direct_end(const Color& L) {
  if (PathRecorder* rec = active_path_recorder()) rec->on_direct_end(L);
}
// Returns L unchanged.
inline Color record_zero_bounce(const Color& L) {
  if (PathRecorder* rec = active_path_recorder()) rec->on_zero_bounce(L);
  return L;
}

}  // namespace pt
