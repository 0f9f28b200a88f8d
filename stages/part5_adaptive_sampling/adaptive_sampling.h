// Part 5: adaptive sampling: stop sampling a pixel once its estimate is
// good enough.
#pragma once
#include <cstdint>

#include "stages/part1_raytracing/pixel_sampling.h"

namespace pt {

struct AdaptiveOptions {
  int batch = 32;           // -a B: check convergence after every B samples
  double tolerance = 0.05;  // -a ... T
};

// The stopping rule. s1 and s2 are the sum and the sum of squares of the
// illuminance of n samples: with mu = s1 / n and
// sigma^2 = (s2 - s1^2 / n) / (n - 1), the pixel has converged when
// 1.96 sigma / sqrt(n) <= T mu (a 95% confidence interval within T of the
// mean). Needs n >= 2.
bool pixel_converged(double s1, double s2, int n, double tolerance);

// Like raytrace_pixel (same samples, same random numbers), but after every
// `batch` samples checks pixel_converged on the samples' illuminance and
// stops early when it holds. Returns the average of the samples taken and
// sets *samples_taken.
Color raytrace_pixel_adaptive(const Camera& cam, int x, int y, int max_samples, uint64_t seed,
                              const RadianceFn& radiance, const AdaptiveOptions& opts, int* samples_taken);

}  // namespace pt
