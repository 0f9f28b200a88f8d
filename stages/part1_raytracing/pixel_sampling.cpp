#include "stages/part1_raytracing/pixel_sampling.h"

#include "stages/part1_raytracing/camera_rays.h"
#include "common/todo.h"

namespace pt {

Ray camera_sample_ray(const Camera& cam, int x, int y, bool jitter, Rng& rng) {
  // BEGIN SOLUTION
  // STUB: PT_TODO(1, "the ray through the pixel centre, never jittered");
  // STUB: unused(jitter, rng);
  // STUB: return generate_ray(cam, (x + 0.5) / cam.width, (y + 0.5) / cam.height);
  double dx = 0.5, dy = 0.5;
  if (jitter) {
    dx = rng.uniform();
    dy = rng.uniform();
  }
  const double u = (x + dx) / cam.width, v = (y + dy) / cam.height;
  if (cam.lens_radius > 0 && cam.thin_lens) return cam.thin_lens(cam, u, v, rng.uniform(), rng.uniform());
  return generate_ray(cam, u, v);
  // END SOLUTION
}

Color raytrace_pixel(const Camera& cam, int x, int y, int num_samples, uint64_t seed,
                     const RadianceFn& radiance) {
  const uint64_t pixel = uint64_t(y) * uint64_t(cam.width) + uint64_t(x);
  // BEGIN SOLUTION
  // STUB: PT_TODO(1, "one sample through the pixel centre, whatever -s");
  // STUB: unused(num_samples);
  // STUB: Rng rng = Rng::for_sample(seed, pixel, 0);
  // STUB: return radiance(camera_sample_ray(cam, x, y, false, rng), rng);
  Color sum(0.0f);
  for (int s = 0; s < num_samples; ++s) {
    Rng rng = Rng::for_sample(seed, pixel, uint64_t(s));
    const Ray r = camera_sample_ray(cam, x, y, num_samples > 1, rng);
    sum += radiance(r, rng);
  }
  return sum / float(num_samples);
  // END SOLUTION
}

}  // namespace pt
