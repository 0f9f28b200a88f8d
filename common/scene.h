// The scene model: everything the COLLADA loader produces and the renderer
// consumes. Plain data in world space (Y up); no behaviour beyond queries.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <memory>

#include "common/bbox.h"
#include "common/camera.h"
#include "common/environment.h"
#include "common/vec3.h"

namespace pt {

// A triangle with its three vertex positions and (smooth) vertex normals,
// stored flat so that the part 1 intersection code reads one struct.
struct Triangle {
  Vec3 p1, p2, p3;
  Vec3 n1, n2, n3;
  int material = 0;

  BBox bounds() const { BBox b(p1, p2); b.expand(p3); return b; }
};

// An analytic sphere (the course's CGL <sphere> extension).
struct Sphere {
  Vec3 center;
  float radius = 1.0f;
  int material = 0;

  BBox bounds() const { return BBox(center - Vec3(radius), center + Vec3(radius)); }
};

// Every material the course's scene files can name. Diffuse and emission
// are given; mirror, glass and refraction are part 6's BSDFs, microfacet
// part 7's (until their part is rendered they reflect nothing, as in the
// course's starter code; see common/bsdf.h).
enum class MaterialType { Diffuse, Emission, Mirror, Glass, Refraction, Microfacet };

struct BSDFModel;   // common/bsdf.h
class EnvironmentSampler;  // common/lights.h

const char* to_string(MaterialType t);

struct Material {
  std::string name;
  MaterialType type = MaterialType::Diffuse;
  Color albedo{0.5f};         // diffuse reflectance
  Color emission{0.0f};       // emitted radiance (emission materials)
  Color reflectance{1.0f};    // mirror, glass
  Color transmittance{1.0f};  // glass, refraction
  float roughness = 0.0f;     // glass, refraction
  float ior = 1.5f;           // glass, refraction
  float alpha = 0.5f;         // microfacet roughness
  Color eta{1.0f};            // microfacet (conductor) index of refraction
  Color k{0.0f};              // microfacet absorption

  // The BSDF the lighting code evaluates for this material (common/bsdf.h):
  // set per render to the model of the part that writes it; none means the
  // given default of its type (diffuse; black for a later part's type).
  const BSDFModel* model = nullptr;

  bool is_emissive() const { return emission.x > 0 || emission.y > 0 || emission.z > 0; }
};

enum class LightType { Area, Point, Directional, Ambient, Environment };

const char* to_string(LightType t);

struct Light {
  LightType type = LightType::Point;
  Color radiance{0.0f};   // area/ambient: radiance; point: intensity; directional: radiance

  // Area light: a one-sided parallelogram centred at `position` spanning
  // position ± dim_x/2 ± dim_y/2, emitting into the half-space of `direction`.
  // Point light: `position`. Directional light: `direction` is the way the
  // light travels (unit). Ambient: uniform radiance from the +Y hemisphere.
  // Environment: radiance from every direction, from `environment`.
  Vec3 position;
  Vec3 direction;
  Vec3 dim_x, dim_y;

  // Environment light (-e): the map of radiance from every direction, and
  // how it is sampled: none = uniformly over the sphere (given); part 8's
  // importance sampling when the render sets one (common/lights.h).
  std::shared_ptr<const EnvironmentMap> environment;
  std::shared_ptr<const EnvironmentSampler> sampler;

  // COLLADA point-light attenuation 1 / (c + l d + q d^2).
  float constant_attenuation = 1.0f;
  float linear_attenuation = 0.0f;
  float quadratic_attenuation = 0.0f;

  bool is_delta() const { return type == LightType::Point || type == LightType::Directional; }
};

struct Scene {
  std::string source;                 // file it was loaded from (for messages)
  std::vector<Triangle> triangles;
  std::vector<Sphere> spheres;
  std::vector<Material> materials;    // never empty after loading
  std::vector<Light> lights;
  Camera camera;

  size_t num_primitives() const { return triangles.size() + spheres.size(); }
  // Bounds of all triangles and spheres (lights excluded).
  BBox bounds() const;
};

}  // namespace pt
