// The per-sample random number generator.
#include <catch2/catch.hpp>
#include <set>

#include "common/rng.h"

using namespace pt;

TEST_CASE("per-sample generators are reproducible and distinct", "[rng]") {
  Rng a = Rng::for_sample(7, 1234, 5), b = Rng::for_sample(7, 1234, 5);
  for (int i = 0; i < 100; ++i) REQUIRE(a.next_u32() == b.next_u32());
  // Neighbouring pixels, samples and seeds start from different numbers.
  std::set<uint32_t> firsts;
  for (uint64_t seed = 0; seed < 4; ++seed)
    for (uint64_t px = 0; px < 64; ++px)
      for (uint64_t s = 0; s < 16; ++s) firsts.insert(Rng::for_sample(seed, px, s).next_u32());
  CHECK(firsts.size() == 4 * 64 * 16);
}

TEST_CASE("uniform() lies in the unit interval and passes a chi-square test", "[rng]") {
  // One chi-square test, alpha = 0.01, 64 equal cells, 640k draws taken as
  // the first draw of consecutive samples (how the renderer uses them).
  // Deterministic seeds, so it either always passes or always fails.
  const int cells = 64, n = 640000;
  std::vector<int> count(cells, 0);
  for (int i = 0; i < n; ++i) {
    Rng r = Rng::for_sample(1, uint64_t(i / 64), uint64_t(i % 64));
    const float u = r.uniform();
    REQUIRE(u >= 0.0f);
    REQUIRE(u < 1.0f);
    ++count[int(u * cells)];
  }
  const double expected = double(n) / cells;
  double chi2 = 0;
  for (int c : count) chi2 += (c - expected) * (c - expected) / expected;
  // Critical value of chi-square with 63 degrees of freedom at alpha = 0.01.
  CHECK(chi2 < 92.01);
}
