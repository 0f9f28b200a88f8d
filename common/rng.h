// Random numbers that do not depend on the thread schedule.
//
// Every sample draws from its own generator, seeded from (image seed, pixel,
// sample index). An image is therefore bit-identical for any thread count
// and any tile order, and a grader gets independent renders by changing the
// image seed. The generator is PCG32 (O'Neill 2014): 64-bit state, 32-bit
// output, statistically strong and tiny.
#pragma once
#include <cstdint>

namespace pt {

// SplitMix64 finaliser: a bijective mix used to turn structured seeds
// (0, 1, 2, ...) into well-spread generator states.
inline uint64_t mix64(uint64_t z) {
  z += 0x9e3779b97f4a7c15ull;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

class Rng {
 public:
  explicit Rng(uint64_t seed = 0, uint64_t stream = 0) {
    inc_ = (stream << 1u) | 1u;
    state_ = 0;
    next_u32();
    state_ += seed;
    next_u32();
  }

  // The generator for sample `sample` of pixel `pixel` in an image rendered
  // with `image_seed`.
  static Rng for_sample(uint64_t image_seed, uint64_t pixel, uint64_t sample) {
    const uint64_t a = mix64(image_seed ^ mix64(pixel));
    return Rng(mix64(a ^ mix64(sample + 0x632be59bd9b4e019ull)), a);
  }

  uint32_t next_u32() {
    const uint64_t old = state_;
    state_ = old * 6364136223846793005ull + inc_;
    const uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
    const uint32_t rot = uint32_t(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
  }

  // Same state: the same numbers from here on (the path inspector counts
  // the draws between two events this way).
  bool operator==(const Rng& o) const { return state_ == o.state_ && inc_ == o.inc_; }
  bool operator!=(const Rng& o) const { return !(*this == o); }

  // Uniform in [0, 1): 24 random mantissa bits, never returns 1.
  float uniform() { return float(next_u32() >> 8) * (1.0f / 16777216.0f); }

  // Uniform in [0, 1) with 53 random bits.
  double uniform_double() {
    const uint64_t hi = next_u32() >> 5, lo = next_u32() >> 6;
    return double((hi << 26) | lo) * (1.0 / 9007199254740992.0);
  }

 private:
  uint64_t state_ = 0, inc_ = 1;
};

}  // namespace pt
