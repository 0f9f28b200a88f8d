// The readers under test and their contract (see loader_checks.h).
#include "instructors/fuzz/loader_checks.h"

#include <array>
#include <cctype>
#include <cmath>
#include <exception>
#include <limits>
#include <stdexcept>
#include <string>
#include <typeinfo>
#include <vector>

#include "stages/part2_bvh/bvh.h"
#include "common/camera.h"
#include "common/collada.h"
#include "common/environment.h"
#include "common/scene.h"
#include "stages/part8_environment_light/environment_sampling.h"
#include "stages/part9_depth_of_field/thin_lens.h"

namespace fuzz {

namespace {

// A message reduced to its shape: numbers, quoted text and ids removed.
std::string shape(const std::string& path, std::string m) {
  if (m.rfind(path + ": ", 0) == 0) m = m.substr(path.size() + 2);
  std::string out;
  for (size_t i = 0; i < m.size() && out.size() < 90; ++i) {
    const char c = m[i];
    if (std::isdigit(static_cast<unsigned char>(c))) {
      if (out.empty() || out.back() != '#') out += '#';
    } else if (c == '\'' || c == '"') {
      const size_t e = m.find(c, i + 1);
      if (e == std::string::npos) break;
      out += "..";
      i = e;
    } else {
      out += c;
    }
  }
  return out;
}

bool one_line_from(const std::string& m, const std::string& path) {
  return m.rfind(path + ": ", 0) == 0 && m.find('\n') == std::string::npos && m.find('\r') == std::string::npos;
}

bool unit(const pt::Vec3& n) { return pt::is_finite(n) && std::fabs(pt::norm(n) - 1.0f) < 1e-3f; }

std::string check_scene(const pt::Scene& s) {
  if (s.num_primitives() == 0) return "a scene without primitives was accepted";
  if (s.num_primitives() > pt::kMaxScenePrimitives) return "more primitives than the limit";
  for (const pt::Triangle& t : s.triangles) {
    if (!pt::is_finite(t.p1) || !pt::is_finite(t.p2) || !pt::is_finite(t.p3)) return "a triangle is not finite";
    if (!unit(t.n1) || !unit(t.n2) || !unit(t.n3)) return "a triangle normal is not unit length";
    if (t.material < 0 || size_t(t.material) >= s.materials.size()) return "a triangle's material is out of range";
  }
  for (const pt::Sphere& sp : s.spheres) {
    if (!pt::is_finite(sp.center) || !(sp.radius > 0) || !std::isfinite(sp.radius)) return "a sphere is degenerate";
    if (sp.material < 0 || size_t(sp.material) >= s.materials.size()) return "a sphere's material is out of range";
  }
  for (const pt::Light& l : s.lights)
    if (!pt::is_finite(l.radiance) || !pt::is_finite(l.position) || !pt::is_finite(l.direction))
      return "a light is not finite";
  const pt::Camera& c = s.camera;
  if (!pt::is_finite(c.position) || !pt::is_finite(c.axis_x) || !pt::is_finite(c.axis_y) || !pt::is_finite(c.axis_z))
    return "the camera is not finite";
  if (!(c.hfov_deg > 0 && c.hfov_deg < 180 && c.vfov_deg > 0 && c.vfov_deg < 180)) return "the camera's FOV is out of range";
  if (!(c.near_clip >= 0 && c.far_clip > c.near_clip)) return "the camera's clip range is wrong";
  return "";
}

// The BVH over a loaded scene (part 2's build, under the sanitizers: its
// binning turns centroid coordinates into bin numbers, which a scene with
// coordinates near 1e38 or a zero extent must not make undefined), and a
// few rays through it: every hit inside the ray's interval, with a unit
// normal. Scenes over kMaxBvhPrimitives are skipped to keep runs short.
constexpr size_t kMaxBvhPrimitives = 20000;

std::string check_bvh(const pt::Scene& s, Random& rng) {
  if (s.num_primitives() > kMaxBvhPrimitives) return "";
  const pt::BVH bvh(s);
  const pt::BBox b = s.bounds();
  for (int i = 0; i < 16; ++i) {
    const auto lerp = [&](float lo, float hi) { return float(lo + (double(hi) - lo) * rng.uniform()); };
    const pt::Vec3 o(lerp(b.lo.x, b.hi.x), lerp(b.lo.y, b.hi.y), lerp(b.lo.z, b.hi.z));
    pt::Vec3 d(float(rng.uniform() * 2 - 1), float(rng.uniform() * 2 - 1), float(rng.uniform() * 2 - 1));
    if (pt::norm(d) < 1e-3f) continue;
    d = pt::normalize(d);
    pt::Ray r(o, d, 1e-4f, std::numeric_limits<float>::infinity());
    pt::Hit hit;
    if (bvh.intersect(r, &hit)) {
      if (!(hit.t >= 1e-4f && hit.t == r.max_t)) return "a BVH hit lies outside the ray's interval";
      if (!unit(hit.n)) return "a BVH hit's normal is not unit length";
    }
    bvh.occluded(pt::Ray(o, d, 1e-4f, 1.0f));
  }
  return "";
}

std::string check_camera(const pt::Camera& c, Random& rng) {
  if (!pt::is_finite(c.position) || !std::isfinite(c.focal_distance) || !(c.focal_distance > 0) ||
      !(c.lens_radius >= 0) || !std::isfinite(c.lens_radius))
    return "the camera holds a non-finite or out-of-range value";
  for (int i = 0; i < 4; ++i) {
    const pt::Ray r =
        pt::generate_ray_for_thin_lens(c, rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform());
    if (!pt::is_finite(r.d)) return "a thin-lens ray from the camera is not finite";
  }
  return "";
}

std::string check_map(const pt::EnvironmentMap& env, Random& rng) {
  if (env.width < 1 || env.height < 1 || env.texels.size() != size_t(env.width) * size_t(env.height))
    return "the map's size does not match its texels";
  for (const pt::Color& c : env.texels)
    if (!pt::is_finite(c) || c.x < 0 || c.y < 0 || c.z < 0) return "a texel is negative or not finite";
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const pt::Vec3 odd[] = {{nan, nan, nan}, {inf, 0, 0}, {0, -inf, inf}, {0, 0, 0}, {1e38f, -1e38f, 1e38f}};
  for (const pt::Vec3& d : odd)
    if (!pt::is_finite(env.lookup(d))) return "a lookup returned a non-finite colour";
  for (int i = 0; i < 8; ++i) {
    const pt::Vec3 d(float(rng.uniform() * 2 - 1), float(rng.uniform() * 2 - 1), float(rng.uniform() * 2 - 1));
    env.lookup(d);
  }
  // Part 8's importance sampling of the map: finite samples and densities.
  const pt::EnvironmentDistribution dist = pt::build_environment_distribution(env);
  for (int i = 0; i < 8; ++i) {
    const pt::LightSample s = pt::sample_environment(dist, env, float(rng.uniform()), float(rng.uniform()));
    if (!pt::is_finite(s.wi) || !std::isfinite(s.pdf) || !(s.pdf >= 0) || !pt::is_finite(s.radiance))
      return "an importance sample of the map is not finite";
  }
  return "";
}

}  // namespace

Outcome read_input(Kind kind, const std::string& path, Random& rng) {
  Outcome o;
  const std::string k = kind_name(kind);
  try {
    if (kind == Kind::Scene) {
      std::vector<std::string> warnings;
      const pt::Scene scene = pt::load_collada(path, &warnings);
      for (const std::string& w : warnings)
        if (!one_line_from(w, path)) o.finding = "a warning is not one line starting with the path: " + w;
      if (o.finding.empty()) o.finding = check_scene(scene);
      if (o.finding.empty()) o.finding = check_bvh(scene, rng);
      o.key = k + " loaded" + (warnings.empty() ? "" : " with warnings: " + shape(path, warnings.front()));
    } else if (kind == Kind::Camera) {
      pt::Camera cam;
      cam.load_settings(path);
      o.finding = check_camera(cam, rng);
      o.key = k + " loaded";
    } else {
      const pt::EnvironmentMap env = pt::load_environment_map(path);
      o.finding = check_map(env, rng);
      o.key = k + " loaded";
    }
  } catch (const pt::SceneError& e) {
    if (kind != Kind::Scene) o.finding = std::string("unexpected SceneError: ") + e.what();
    else if (!one_line_from(e.what(), path)) o.finding = std::string("a message not of one line naming the file: ") + e.what();
    o.key = k + " refused: " + shape(path, e.what());
  } catch (const std::runtime_error& e) {
    // Exactly std::runtime_error for the camera and the map; a SceneError
    // for scenes (caught above).
    if (kind == Kind::Scene || typeid(e) != typeid(std::runtime_error))
      o.finding = std::string("unexpected exception type ") + typeid(e).name() + ": " + e.what();
    else if (!one_line_from(e.what(), path))
      o.finding = std::string("a message not of one line naming the file: ") + e.what();
    o.key = k + " refused: " + shape(path, e.what());
  } catch (const std::exception& e) {
    o.finding = std::string("unexpected exception ") + typeid(e).name() + ": " + e.what();
    o.key = k + " threw " + typeid(e).name();
  }
  return o;
}

// Fixed probes of the BVH build at the edges of float that random
// mutation seldom reaches: coordinates spanning +-3e38 (extents and
// centroids overflow to infinity), one centroid shared by every triangle,
// and triangles a few denormals wide. Under the sanitizers, a bin number
// converted from NaN or infinity aborts the run here.
std::string probe_bvh_extremes() {
  const float big = 3.0e38f, tiny = 1e-42f;
  const auto scene_of = [](const std::vector<std::array<pt::Vec3, 3>>& tris) {
    pt::Scene s;
    s.materials.push_back(pt::Material{});
    for (const auto& t : tris) {
      pt::Triangle tri;
      tri.p1 = t[0], tri.p2 = t[1], tri.p3 = t[2];
      tri.n1 = tri.n2 = tri.n3 = pt::Vec3(0, 0, 1);
      s.triangles.push_back(tri);
    }
    return s;
  };
  std::vector<std::vector<std::array<pt::Vec3, 3>>> cases(3);
  for (int i = 0; i < 40; ++i) {
    const float x = (i % 2 ? big : -big) * (1.0f - 0.01f * float(i));
    cases[0].push_back({pt::Vec3(x, 0, 0), pt::Vec3(x, 1, 0), pt::Vec3(-x, 0, 1)});
    cases[1].push_back({pt::Vec3(-1, -1, 0), pt::Vec3(1, 1, 0), pt::Vec3(0, 0, float(i % 3) - 1)});
    cases[2].push_back({pt::Vec3(tiny * float(i), 0, 0), pt::Vec3(tiny * float(i + 1), 0, 0), pt::Vec3(0, tiny, 0)});
  }
  for (const auto& c : cases) {
    const pt::Scene s = scene_of(c);
    const pt::BVH bvh(s);
    pt::Ray r(pt::Vec3(0, 0, -1), pt::Vec3(0, 0, 1), 0.0f, std::numeric_limits<float>::infinity());
    pt::Hit hit;
    bvh.intersect(r, &hit);
    // Through the interface (a BVH's layout is its own): the scene's box
    // holds every primitive.
    const pt::BBox all = bvh.bounds();
    for (const pt::Triangle& t : s.triangles) {
      const pt::BBox b = t.bounds();
      if (!(all.lo.x <= b.lo.x && all.lo.y <= b.lo.y && all.lo.z <= b.lo.z && all.hi.x >= b.hi.x &&
            all.hi.y >= b.hi.y && all.hi.z >= b.hi.z))
        return "the BVH lost primitives (its bounds miss one)";
    }
  }
  return "";
}

}  // namespace fuzz
