#include "common/scene.h"

namespace pt {

const char* to_string(MaterialType t) {
  switch (t) {
    case MaterialType::Diffuse: return "diffuse";
    case MaterialType::Emission: return "emission";
    case MaterialType::Mirror: return "mirror";
    case MaterialType::Glass: return "glass";
    case MaterialType::Refraction: return "refraction";
    case MaterialType::Microfacet: return "microfacet";
  }
  return "?";
}

const char* to_string(LightType t) {
  switch (t) {
    case LightType::Area: return "area";
    case LightType::Point: return "point";
    case LightType::Directional: return "directional";
    case LightType::Ambient: return "ambient";
    case LightType::Environment: return "environment";
  }
  return "?";
}

BBox Scene::bounds() const {
  BBox b;
  for (const Triangle& t : triangles) b.expand(t.bounds());
  for (const Sphere& s : spheres) b.expand(s.bounds());
  return b;
}

}  // namespace pt
