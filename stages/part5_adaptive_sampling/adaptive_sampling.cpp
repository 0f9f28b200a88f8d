#include "stages/part5_adaptive_sampling/adaptive_sampling.h"

#include <cmath>

#include "common/todo.h"

namespace pt {

bool pixel_converged(double s1, double s2, int n, double tolerance) {
  // BEGIN SOLUTION
  // STUB: PT_TODO(5, "no pixel ever converges");
  // STUB: unused(s1, s2, n, tolerance);
  // STUB: return false;
  if (n < 2) return false;
  const double mean = s1 / n;
  const double variance = std::fmax(0.0, (s2 - s1 * s1 / n) / (n - 1));
  return 1.96 * std::sqrt(variance) / std::sqrt(double(n)) <= tolerance * mean;
  // END SOLUTION
}

Color raytrace_pixel_adaptive(const Camera& cam, int x, int y, int max_samples, uint64_t seed,
                              const RadianceFn& radiance, const AdaptiveOptions& opts, int* samples_taken) {
  const uint64_t pixel = uint64_t(y) * uint64_t(cam.width) + uint64_t(x);
  // BEGIN SOLUTION
  // STUB: PT_TODO(5, "every pixel takes all -s samples (raytrace_pixel)");
  // STUB: unused(pixel, opts);
  // STUB: *samples_taken = max_samples;
  // STUB: return raytrace_pixel(cam, x, y, max_samples, seed, radiance);
  Color sum(0.0f);
  double s1 = 0, s2 = 0;
  int n = 0;
  while (n < max_samples) {
    Rng rng = Rng::for_sample(seed, pixel, uint64_t(n));
    const Color L = radiance(camera_sample_ray(cam, x, y, max_samples > 1, rng), rng);
    sum += L;
    const double xi = illum(L);
    s1 += xi;
    s2 += xi * xi;
    ++n;
    if (n % opts.batch == 0 && n < max_samples && pixel_converged(s1, s2, n, opts.tolerance)) break;
  }
  *samples_taken = n;
  return sum / float(n);
  // END SOLUTION
}

}  // namespace pt
