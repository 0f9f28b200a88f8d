#include "stages/part1_raytracing/shading.h"

namespace pt {

Color normal_shading(const Intersector& scene, const Ray& ray) {
  Ray r = ray;
  Hit hit;
  if (!scene.intersect(r, &hit)) return Color(0.0f);
  return hit.n * 0.5f + Color(0.5f);
}

}  // namespace pt
