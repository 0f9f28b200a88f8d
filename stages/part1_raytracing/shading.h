// Shading used before lighting exists (parts 1 and 2): the surface normal
// mapped to a colour.
#pragma once
#include "common/intersector.h"

namespace pt {

// n * 0.5 + 0.5 at the nearest hit, black when the ray escapes.
Color normal_shading(const Intersector& scene, const Ray& ray);

}  // namespace pt
