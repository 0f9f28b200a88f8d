#include "viewer/progressive.h"

#include <algorithm>
#include <cstring>

namespace pt::viewer {

namespace {

// The calling render thread's pixel and sample, and what it counted.
struct ThreadPixel {
  long long index = 0;
  int sample = 0;
  uint64_t traced = 0, reused = 0;
};
thread_local ThreadPixel t_pixel;

// A 32-bit key of a sample's camera ray and generator state: the sample is
// the same as one traced before when both are (a pixel function that
// follows the contract draws sample s from Rng::for_sample(seed, pixel, s)).
// Computed for every sample of every pass: a few multiplications.
uint32_t sample_key(const Ray& r, const Rng& rng) {
  static_assert(sizeof(Rng) == 16, "the generator's state is two 64-bit words");
  uint64_t w[6];
  std::memcpy(w, &rng, 16);
  std::memcpy(&w[2], &r.o, 12);
  std::memcpy(reinterpret_cast<char*>(&w[2]) + 12, &r.d, 12);
  std::memcpy(&w[5], &r.min_t, 4);
  std::memcpy(reinterpret_cast<char*>(&w[5]) + 4, &r.max_t, 4);
  uint64_t h = 0x243f6a8885a308d3ull;
  for (uint64_t x : w) h = (h ^ x) * 0x9e3779b97f4a7c15ull;
  h ^= h >> 29;
  return uint32_t(h ^ (h >> 32));
}

}  // namespace

std::vector<int> pass_schedule(int target, long long keep) {
  std::vector<int> passes = {1};
  if (target <= 1) return passes;
  for (long long n = 2; n < target && n <= keep; n *= 2) passes.push_back(int(n));
  passes.push_back(target);
  return passes;
}

long long samples_kept(long long pixels) {
  return pixels > 0 ? (long long)(kSampleCacheBytes / (size_t(pixels) * 16)) : 0;
}

SampleCache::SampleCache(long long pixels, int per_pixel)
    : pixels_(pixels), per_pixel_(std::max(0, per_pixel)) {
  static_assert(sizeof(Entry) == 16, "16 bytes a kept sample");
  if (per_pixel_ > 0) {
    // Not initialised: an entry is read only below its pixel's count.
    entries_.reset(new Entry[size_t(pixels_) * size_t(per_pixel_)]);
    count_.assign(size_t(pixels_), 0);
  }
}

void SampleCache::set_pixel(long long index) {
  t_pixel.index = index;
  t_pixel.sample = 0;
}

void SampleCache::end_pixel() {
  // Each thread its own slot (threads beyond kCountSlots share).
  static std::atomic<int> next_slot{0};
  thread_local const int slot = next_slot++ % kCountSlots;
  Counts& c = counts_[slot];
  c.traced.fetch_add(t_pixel.traced, std::memory_order_relaxed);
  c.reused.fetch_add(t_pixel.reused, std::memory_order_relaxed);
  t_pixel.traced = t_pixel.reused = 0;
}

void SampleCache::take_counts(uint64_t* traced, uint64_t* reused) {
  *traced = *reused = 0;
  for (Counts& c : counts_) {
    *traced += c.traced.exchange(0);
    *reused += c.reused.exchange(0);
  }
}

RadianceFn SampleCache::wrap(RadianceFn trace, bool keep) {
  return [this, trace = std::move(trace), keep](const Ray& r, Rng& rng) -> Color {
    ThreadPixel& px = t_pixel;
    const int s = px.sample++;
    if (s >= per_pixel_ || px.index < 0 || px.index >= pixels_) {
      ++px.traced;
      return trace(r, rng);
    }
    uint32_t& count = count_[size_t(px.index)];
    const bool kept = uint32_t(s) < count, to_keep = keep && uint32_t(s) <= count;
    if (!kept && !to_keep) {
      ++px.traced;
      return trace(r, rng);
    }
    const uint32_t key = sample_key(r, rng);
    Entry& e = entries_[size_t(px.index) * size_t(per_pixel_) + size_t(s)];
    if (kept && e.key == key) {
      ++px.reused;
      return e.value;
    }
    ++px.traced;
    const Color L = trace(r, rng);
    // Kept in order: sample s once 0 .. s - 1 are.
    if (to_keep) {
      e.value = L;
      e.key = key;
      if (uint32_t(s) == count) ++count;
    }
    return L;
  };
}

void render_progressive(const Scene& scene, const RenderOptions& base, const PassHooks& hooks) {
  const int x0 = base.cell_set ? base.cell_x : 0, y0 = base.cell_set ? base.cell_y : 0;
  const int cw = base.cell_set ? base.cell_w : base.width, ch = base.cell_set ? base.cell_h : base.height;
  const std::vector<int> passes = pass_schedule(base.samples_per_pixel, samples_kept((long long)cw * ch));
  // The last pass reuses the samples of the one before it.
  SampleCache cache((long long)cw * ch, passes.size() > 2 ? passes[passes.size() - 2] : 0);
  RenderCache geometry;  // the BVH is built by the first pass and reused
  for (int pass = 0; pass < int(passes.size()); ++pass) {
    RenderOptions o = base;
    o.samples_per_pixel = passes[size_t(pass)];
    o.progress = false;
    RenderHooks rh;
    rh.before_pixel = [&](int x, int y) {
      if (hooks.before_pixel) hooks.before_pixel(pass, x, y);
      SampleCache::set_pixel((long long)(y - y0) * cw + (x - x0));
    };
    rh.after_pixel = [&](int x, int y) {
      cache.end_pixel();
      if (hooks.after_pixel) hooks.after_pixel(pass, x, y);
    };
    // Kept for the next pass: every pass's jittered samples but the last's.
    const bool keep = o.samples_per_pixel > 1 && pass + 1 < int(passes.size());
    rh.wrap_radiance = [&](RadianceFn trace) { return cache.wrap(std::move(trace), keep); };
    const RenderResult r = render_scene(scene, o, rh, &geometry);
    uint64_t traced = 0, reused = 0;
    cache.take_counts(&traced, &reused);
    if (hooks.pass_done) hooks.pass_done(pass, o, r, traced, reused);
  }
}

}  // namespace pt::viewer
