// The generator's scene description: everything is stated in world space
// (Y up, the renderer's convention) and converted to the course's Z_UP file
// coordinates only when written. Plain data and a few geometric helpers; no
// dependencies beyond the standard library.
#pragma once
#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace scenegen {

struct V3 {
  double x = 0, y = 0, z = 0;
};

inline V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline V3 operator*(double s, V3 a) { return {s * a.x, s * a.y, s * a.z}; }
inline double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline V3 cross(V3 a, V3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double length(V3 a) { return std::sqrt(dot(a, a)); }
inline V3 normalize(V3 a) { return (1.0 / length(a)) * a; }

// Z_UP file coordinates (x', y', z') are world (-x', z', y'). The map is its
// own inverse, so the same function converts in both directions.
inline V3 zup_to_world(V3 f) { return {-f.x, f.z, f.y}; }
inline V3 world_to_zup(V3 w) { return {-w.x, w.z, w.y}; }

// A node's transform in world space: the images of the local x, y, z axes
// (columns, scale included) and the translation.
struct Xform {
  V3 ax{1, 0, 0}, ay{0, 1, 0}, az{0, 0, 1};
  V3 t{};
};

// The frame a Blender (Z-up) node has with no rotation: local axes equal the
// file's axes, seen in world space.
inline Xform zup_frame(V3 world_translation, double sx = 1, double sy = 1, double sz = 1) {
  Xform x;
  x.ax = sx * zup_to_world({1, 0, 0});
  x.ay = sy * zup_to_world({0, 1, 0});
  x.az = sz * zup_to_world({0, 0, 1});
  x.t = world_translation;
  return x;
}

// A camera frame at `position` looking along -dir_to_camera (local -Z), with
// world +Y as the image's up direction.
inline Xform camera_frame(V3 position, V3 dir_to_camera) {
  Xform x;
  x.az = normalize(dir_to_camera);
  x.ax = normalize(cross(V3{0, 1, 0}, x.az));
  x.ay = cross(x.az, x.ax);
  x.t = position;
  return x;
}

// The node's <matrix> in file coordinates, row-major: M = U * W where U is
// the up-axis map (U * U = identity), i.e. every column converted to Z_UP.
inline std::array<double, 16> node_matrix(const Xform& w) {
  const V3 a = world_to_zup(w.ax), b = world_to_zup(w.ay), c = world_to_zup(w.az);
  const V3 t = world_to_zup(w.t);
  return {a.x, b.x, c.x, t.x,  //
          a.y, b.y, c.y, t.y,  //
          a.z, b.z, c.z, t.z,  //
          0,   0,   0,   1};
}

using Rgb = std::array<double, 3>;

enum class MaterialKind { Diffuse, Emission, Mirror, Glass, Microfacet };

struct Material {
  std::string name;              // ids: NAME-effect, NAME-material
  MaterialKind kind = MaterialKind::Diffuse;
  Rgb diffuse{0.5, 0.5, 0.5};    // profile_COMMON phong diffuse (the fallback look)
  Rgb emission{0, 0, 0};         // CGL emission radiance
  Rgb reflectance{1, 1, 1};      // CGL mirror / glass
  Rgb transmittance{1, 1, 1};    // CGL glass
  double roughness = 0;          // CGL glass
  double ior = 1.5;              // CGL glass
  double alpha = 0.5;            // CGL microfacet: Beckmann roughness
  Rgb eta{1, 1, 1};              // CGL microfacet: the metal's index of refraction per channel
  Rgb k{0, 0, 0};                // CGL microfacet: its extinction coefficient per channel
};

// A triangle mesh; vertices in world space, triangles as vertex indices in
// the order they are written (the winding is part of the scene's facts).
struct Mesh {
  std::string name;
  std::string material;
  std::vector<V3> vertices;
  std::vector<std::array<int, 3>> triangles;
  // A closed surface: every edge is shared by exactly two triangles, wound
  // counter-clockwise seen from outside. The generator checks it.
  bool closed = false;
};

// An analytic sphere (the course's CGL <sphere> geometry).
struct Sphere {
  std::string name;
  std::string material;
  V3 center;       // world space
  double radius = 1;
};

enum class LightKind { Point, Area, Ambient, Directional };

struct Light {
  std::string name;
  LightKind kind = LightKind::Point;
  Rgb color{1, 1, 1};             // point: intensity; area/ambient: radiance
  double constant_attenuation = 1;
  double linear_attenuation = 0;
  double quadratic_attenuation = 0;
  Xform node;                     // position; area lights: size and facing too;
                                  // directional lights shine along the node's -Z
};

struct Scene {
  std::string file;               // e.g. "CBempty.dae"
  std::string purpose;            // one line, written as a comment in the file
  Xform camera;
  std::vector<Material> materials;
  std::vector<Mesh> meshes;
  std::vector<Sphere> spheres;
  std::vector<Light> lights;

  size_t triangle_count() const {
    size_t n = 0;
    for (const Mesh& m : meshes) n += m.triangles.size();
    return n;
  }
};

}  // namespace scenegen
