// The viewer's progressive render: passes of 1, 2, 4, ... samples per
// pixel and then -s, each pass exactly the command line's image at its
// sample count (the same pixel function, radiance function and
// Rng::for_sample streams), where a pass does not trace again the samples
// the pass before it traced.
//
// How: the pixel function (raytrace_pixel, or part 5's
// raytrace_pixel_adaptive) calls the radiance function once per sample, in
// order. The viewer hands it one that, for a sample whose camera ray and
// generator are those of a sample it traced in an earlier pass (a 32-bit
// key of both is kept with each value), returns that sample's value, and
// traces the others. The pixel function adds the values up itself, as in
// the command line, so every pass's pixel is the command line's bit for
// bit, whatever a student's pixel function does with them. Pass 1 (one
// sample through the pixel centre) is the only one not reused: from 2
// samples on, the rays are jittered.
//
// What is kept: 16 bytes per sample per pixel of the image (or the cell),
// for the samples of the passes before the last; at most
// kSampleCacheBytes. The passes stop doubling where the kept samples would
// not fit: a render too large to keep 2 samples a pixel shows 1 sample,
// then -s.
#pragma once
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "common/ray.h"
#include "common/rng.h"
#include "pathtracer/options.h"
#include "pathtracer/render_job.h"
#include "stages/part1_raytracing/pixel_sampling.h"

namespace pt::viewer {

constexpr size_t kSampleCacheBytes = size_t(512) << 20;

// The samples per pixel of each pass for -s `target` when `keep` samples
// per pixel may be kept between passes: 1, then 2, 4, ... up to `keep`
// while below `target`, then `target`.
std::vector<int> pass_schedule(int target, long long keep);

// How many samples per pixel fit in kSampleCacheBytes for `pixels` pixels.
long long samples_kept(long long pixels);

// The samples traced so far, per pixel, for the passes that follow.
class SampleCache {
 public:
  // `pixels` pixels, up to `per_pixel` samples each (0: none kept).
  SampleCache(long long pixels, int per_pixel);

  // The radiance function for the pixel function of one pass: sample s of
  // the calling thread's pixel (set_pixel) is taken from the cache when it
  // is there with the same ray and generator, else traced with `trace`
  // (and kept, when `keep` and there is room).
  RadianceFn wrap(RadianceFn trace, bool keep);

  // The calling thread's next calls are for pixel `index` (0-based within
  // the image or cell), sample 0 first; end_pixel after its last.
  static void set_pixel(long long index);
  void end_pixel();

  // Samples traced and samples reused since the last call.
  void take_counts(uint64_t* traced, uint64_t* reused);

 private:
  struct Entry {
    Color value;
    uint32_t key;
  };
  long long pixels_;
  int per_pixel_;
  std::unique_ptr<Entry[]> entries_;  // pixel-major, per_pixel_ each; written before read
  std::vector<uint32_t> count_;       // samples kept per pixel, 0 .. count - 1
  // Counts of samples traced and reused, one slot (a cache line) per
  // thread: threads adding to one shared counter after every pixel slowed
  // a render by 1 %.
  struct alignas(64) Counts {
    std::atomic<uint64_t> traced{0}, reused{0};
  };
  static constexpr int kCountSlots = 64;
  Counts counts_[kCountSlots];
};

// What render_progressive tells its caller.
struct PassHooks {
  // On the render thread, before and after each pixel of pass `pass`
  // (0-based).
  std::function<void(int pass, int x, int y)> before_pixel, after_pixel;
  // After each pass: its options (the pass's sample count), its result,
  // and how many samples it traced and took from the passes before.
  std::function<void(int pass, const RenderOptions& o, const RenderResult& r, uint64_t traced, uint64_t reused)>
      pass_done;
};

// Renders `base` (scene's camera configured for it) pass by pass, as the
// page shows it: pass_schedule(-s, what fits), each pass render_scene with
// that sample count and a SampleCache between them.
void render_progressive(const Scene& scene, const RenderOptions& base, const PassHooks& hooks);

}  // namespace pt::viewer
