// What fuzz_loaders works on: its random numbers, the three kinds of input
// and a seed file.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace fuzz {

// ---- Random numbers (SplitMix64: the same sequence on every platform) ----

struct Random {
  uint64_t state;
  explicit Random(uint64_t seed) : state(seed) {}
  uint64_t next() {
    uint64_t z = (state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  size_t below(size_t n) { return n == 0 ? 0 : size_t(next() % n); }
  bool chance(double p) { return double(next() >> 11) * 0x1.0p-53 < p; }
  double uniform() { return double(next() >> 11) * 0x1.0p-53; }
  template <typename T>
  const T& pick(const std::vector<T>& v) { return v[below(v.size())]; }
};

enum class Kind { Scene, Camera, Exr };
inline const char* kind_name(Kind k) { return k == Kind::Scene ? "dae" : k == Kind::Camera ? "camera" : "exr"; }
inline const char* kind_ext(Kind k) { return k == Kind::Scene ? ".dae" : k == Kind::Camera ? ".txt" : ".exr"; }

struct Seed {
  std::string name;
  Kind kind;
  std::string bytes;
};

}  // namespace fuzz
