#include "viewer/debug_api.h"

#include <cmath>
#include <limits>

#include "viewer/debugger/debugger.h"
#include "common/json.h"
#include "viewer/debugger/json_values.h"

namespace pt::viewer {

using debug::InputError;

namespace {

// A number of the input: a JSON number, or "nan", "inf", "-inf" (the
// debugger's own spelling), so that absurd values reach the tools' checks.
double input_number(const Json* v, const std::string& what) {
  if (!v) throw InputError(what + ": missing");
  if (v->type == Json::Type::Number) return v->number;
  if (v->type == Json::Type::String) {
    if (v->string == "nan") return std::numeric_limits<double>::quiet_NaN();
    if (v->string == "inf") return std::numeric_limits<double>::infinity();
    if (v->string == "-inf") return -std::numeric_limits<double>::infinity();
  }
  throw InputError(what + ": expected a number");
}

float input_float(const Json& obj, const std::string& key, const std::string& what) {
  return float(input_number(obj.get(key), what));
}

Vec3 input_vec(const Json& obj, const std::string& key, const std::string& what) {
  const Json* v = obj.get(key);
  if (!v || v->type != Json::Type::Array || v->array.size() != 3) throw InputError(what + ": expected 3 numbers");
  return Vec3(float(input_number(&v->array[0], what)), float(input_number(&v->array[1], what)),
              float(input_number(&v->array[2], what)));
}

long long input_int(const Json& obj, const std::string& key, const std::string& what, long long lo, long long hi) {
  const double d = input_number(obj.get(key), what);
  if (!(d == std::floor(d))) throw InputError(what + ": expected an integer");
  if (d < double(lo) || d > double(hi))
    throw InputError(what + ": " + json_number(d) + " is outside [" + std::to_string(lo) + ", " +
                     std::to_string(hi) + "]");
  return (long long)d;
}

const Json& input_object(const Json& obj, const std::string& key) {
  const Json* v = obj.get(key);
  if (!v || v->type != Json::Type::Object) throw InputError(key + ": expected an object");
  return *v;
}

debug::RayInput input_ray(const Json& in) {
  const Json& r = input_object(in, "ray");
  debug::RayInput ray;
  ray.origin = input_vec(r, "origin", "the ray's origin");
  ray.direction = input_vec(r, "direction", "the ray's direction");
  if (r.get("min_t")) ray.min_t = input_float(r, "min_t", "min_t");
  if (r.get("max_t")) ray.max_t = input_float(r, "max_t", "max_t");
  return ray;
}

// The light's shape, for drawing it.
Json light_json(const Light& l) {
  Json o = json_object();
  o.set("type", json_text(to_string(l.type)))
      .set("position", debug::json_vec(l.position))
      .set("direction", debug::json_vec(l.direction))
      .set("dim_x", debug::json_vec(l.dim_x))
      .set("dim_y", debug::json_vec(l.dim_y));
  return o;
}

std::string intersect(const Json& in, const std::function<Scene()>& load) {
  const debug::RayInput ray = input_ray(in);
  if (const Json* t = in.get("triangle"); t && t->type != Json::Type::Null) {
    if (t->type != Json::Type::Object) throw InputError("triangle: expected an object");
    Triangle tri;
    tri.p1 = input_vec(*t, "p1", "the triangle's p1");
    tri.p2 = input_vec(*t, "p2", "the triangle's p2");
    tri.p3 = input_vec(*t, "p3", "the triangle's p3");
    // The face normal as every vertex normal, as a flat mesh has it.
    const Vec3 n = cross(tri.p2 - tri.p1, tri.p3 - tri.p1);
    const float len = norm(n);
    tri.n1 = tri.n2 = tri.n3 = len > 0 && std::isfinite(len) ? n / len : Vec3(0, 0, 1);
    return debug::test_ray_triangle(tri, ray).to_json();
  }
  if (const Json* s = in.get("sphere"); s && s->type != Json::Type::Null) {
    if (s->type != Json::Type::Object) throw InputError("sphere: expected an object");
    Sphere sp;
    sp.center = input_vec(*s, "center", "the sphere's centre");
    sp.radius = input_float(*s, "radius", "the sphere's radius");
    return debug::test_ray_sphere(sp, ray).to_json();
  }
  if (in.get("primitive")) {
    const Scene scene = load();
    const int p = int(input_int(in, "primitive", "primitive", 0, std::numeric_limits<int>::max()));
    debug::IntersectionResult r = debug::test_ray_primitive(scene, p, ray);
    Json j = r.json();
    j.set("primitive", json_int(p));
    if (size_t(p) < scene.triangles.size()) {
      const Triangle& t = scene.triangles[size_t(p)];
      j.set("triangle", json_array({debug::json_vec(t.p1), debug::json_vec(t.p2), debug::json_vec(t.p3)}, true));
    } else {
      const Sphere& s = scene.spheres[size_t(p) - scene.triangles.size()];
      j.set("sphere", json_array({debug::json_vec(s.center), debug::json_float(s.radius)}, true));
    }
    return write_json(j);
  }
  throw InputError("give a triangle, a sphere or a primitive of the scene");
}

std::string lights(const Json& in, const RenderOptions& opts, const std::function<Scene()>& load) {
  const Scene scene = load();
  const long long light = input_int(in, "light", "light", 0, std::numeric_limits<int>::max());
  if (size_t(light) >= scene.lights.size())
    throw InputError("light " + std::to_string(light) + " is out of range: the scene has " +
                     std::to_string(scene.lights.size()) + " light(s)");
  const Vec3 point = input_vec(in, "point", "the point");
  const Vec3 normal = input_vec(in, "normal", "the normal");
  const int n = int(input_int(in, "samples", "samples", 1, debug::kMaxLightSamples));
  const uint64_t seed = uint64_t(input_int(in, "seed", "seed", 0, 9007199254740991LL));
  const bool shadows = !in.get("shadows") || in.flag("shadows", true);
  std::unique_ptr<Intersector> geometry = shadows ? debug::make_geometry(scene, opts) : nullptr;
  const debug::LightSamplesResult r =
      debug::sample_light_many(scene, int(light), point, normal, n, seed, geometry.get());
  Json j = r.json();
  j.set("light_shape", light_json(scene.lights[size_t(light)]));
  return write_json(j);
}

std::string path(const Json& in, const RenderOptions& opts, const std::function<Scene()>& load) {
  const Scene scene = load();
  const int x = int(input_int(in, "x", "x", std::numeric_limits<int>::min(), std::numeric_limits<int>::max()));
  const int y = int(input_int(in, "y", "y", std::numeric_limits<int>::min(), std::numeric_limits<int>::max()));
  const int s =
      int(input_int(in, "sample", "sample", std::numeric_limits<int>::min(), std::numeric_limits<int>::max()));
  // Checked before the BVH is built: an out-of-range pixel costs nothing.
  if (x < 0 || y < 0 || x >= opts.width || y >= opts.height)
    throw InputError("pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") is outside the " +
                     std::to_string(opts.width) + "x" + std::to_string(opts.height) + " image");
  if (s < 0 || s >= opts.samples_per_pixel)
    throw InputError("sample index " + std::to_string(s) + " is out of range: -s " +
                     std::to_string(opts.samples_per_pixel) + " gives samples 0 to " +
                     std::to_string(opts.samples_per_pixel - 1));
  std::unique_ptr<Intersector> geometry = debug::make_geometry(scene, opts);
  return debug::record_path(scene, *geometry, opts, x, y, s).to_json();
}

// The BSDF sampler from the first hit of a pixel's centre ray.
std::string bsdf(const Json& in, const RenderOptions& opts, const std::function<Scene()>& load) {
  const int x = int(input_int(in, "x", "x", std::numeric_limits<int>::min(), std::numeric_limits<int>::max()));
  const int y = int(input_int(in, "y", "y", std::numeric_limits<int>::min(), std::numeric_limits<int>::max()));
  const int n = int(input_int(in, "samples", "samples", 1, debug::kMaxBsdfSamples));
  const uint64_t seed = uint64_t(input_int(in, "seed", "seed", 0, 9007199254740991LL));
  // Checked before the scene is read: an out-of-range pixel costs nothing.
  if (x < 0 || y < 0 || x >= opts.width || y >= opts.height)
    throw InputError("pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") is outside the " +
                     std::to_string(opts.width) + "x" + std::to_string(opts.height) + " image");
  const Scene scene = load();
  std::unique_ptr<Intersector> geometry = debug::make_geometry(scene, opts);
  Json j = debug::sample_bsdf_at_pixel(scene, *geometry, opts, x, y, n, seed).json();
  j.set("pixel", json_array({json_int(x), json_int(y)}, true)).set("part", json_int(opts.part));
  return write_json(j);
}

}  // namespace

bool is_debug_tool(const std::string& tool) {
  return tool == "intersect" || tool == "lights" || tool == "path" || tool == "bsdf" || tool == "envmap";
}

std::string run_debug_tool(const std::string& tool, const std::string& input, const RenderOptions& opts,
                           const std::function<Scene()>& load) {
  Json in;
  try {
    in = parse_json(input, "the debug input");
  } catch (const std::exception& e) {
    throw InputError(e.what());
  }
  if (in.type != Json::Type::Object) throw InputError("the debug input must be a JSON object");
  if (tool == "intersect") return intersect(in, load);
  if (tool == "lights") return lights(in, opts, load);
  if (tool == "path") return path(in, opts, load);
  if (tool == "bsdf") return bsdf(in, opts, load);
  if (tool == "envmap") return debug::environment_density(load(), opts).to_json();
  throw InputError("unknown debug tool '" + tool + "'");
}

}  // namespace pt::viewer
