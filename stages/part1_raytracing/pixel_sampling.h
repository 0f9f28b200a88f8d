// Part 1, task 2: estimating a pixel from several camera samples.
#pragma once
#include <cstdint>
#include <functional>

#include "common/camera.h"
#include "common/ray.h"
#include "common/rng.h"

namespace pt {

// Radiance arriving along a camera ray; draws its random numbers from `rng`.
using RadianceFn = std::function<Color(const Ray& r, Rng& rng)>;

// The camera ray of one sample of pixel (x, y): through the pixel centre
// when `jitter` is false, else through a uniformly random point of the
// pixel, with its random numbers drawn from `rng`. With a thin lens (from
// part 9 on: cam.thin_lens set and cam.lens_radius > 0) the ray is
// cam.thin_lens's, with two more numbers for the point on the lens.
Ray camera_sample_ray(const Camera& cam, int x, int y, bool jitter, Rng& rng);

// The estimate of pixel (x, y) (integer pixel coordinates, (0, 0) at the
// bottom-left) from `num_samples` camera samples.
// Contract: with one sample, the ray through the pixel centre; otherwise
// each sample goes through a uniformly random point of the pixel. Sample s
// draws every random number it needs from Rng::for_sample(seed, pixel, s)
// with pixel = y * width + x. Returns the average radiance.
Color raytrace_pixel(const Camera& cam, int x, int y, int num_samples, uint64_t seed,
                     const RadianceFn& radiance);

}  // namespace pt
