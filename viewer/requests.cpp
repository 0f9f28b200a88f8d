#include "viewer/requests.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace pt::viewer {

namespace {

std::string num(double v) { return pt::json_number(v); }

// Reads members of the JSON object the page sends, checking each as the
// command line checks its flag (absent or null: the fallback).
class SettingsReader {
 public:
  explicit SettingsReader(const Json& j) : j_(j) {}

  double number(const char* key, double lo, double hi, double fallback, bool integer) {
    const Json* v = j_.get(key);
    if (!v || v->type == Json::Type::Null) return fallback;
    if (v->type != Json::Type::Number || !std::isfinite(v->number))
      throw BadRequest(std::string(key) + ": expected a number");
    if (integer && v->number != std::floor(v->number)) throw BadRequest(std::string(key) + ": expected an integer");
    if (v->number < lo || v->number > hi) {
      char buf[160];
      std::snprintf(buf, sizeof buf, "%s: %.10g is outside [%.10g, %.10g]", key, v->number, lo, hi);
      throw BadRequest(buf);
    }
    return v->number;
  }
  bool flag(const char* key, bool fallback) {
    const Json* v = j_.get(key);
    if (!v || v->type == Json::Type::Null) return fallback;
    if (v->type != Json::Type::Bool) throw BadRequest(std::string(key) + ": expected true or false");
    return v->boolean;
  }
  std::string text(const char* key, const std::string& fallback) {
    const Json* v = j_.get(key);
    if (!v || v->type == Json::Type::Null) return fallback;
    if (v->type != Json::Type::String) throw BadRequest(std::string(key) + ": expected a string");
    return v->string;
  }
  std::vector<double> numbers(const char* key, const Json& obj, size_t n) {
    const Json* v = obj.get(key);
    if (!v || v->type != Json::Type::Array || v->array.size() != n)
      throw BadRequest(std::string(key) + ": expected " + std::to_string(n) + " numbers");
    std::vector<double> out;
    for (const Json& e : v->array) {
      if (e.type != Json::Type::Number || !std::isfinite(e.number) || std::fabs(e.number) > 1e12)
        throw BadRequest(std::string(key) + ": expected " + std::to_string(n) + " finite numbers");
      out.push_back(e.number);
    }
    return out;
  }

  const Json& json() const { return j_; }

 private:
  const Json& j_;
};

// A file the page names: resolved inside the allowed folders (403 when it
// is not there). An empty name stays empty where `optional`.
std::string read_file_setting(SettingsReader& r, const char* key, const std::string& fallback, FileKind kind,
                              const FileAccess& files, bool optional) {
  const std::string name = r.text(key, fallback);
  if (optional && name.empty()) return "";
  std::string why;
  const std::string path = files.resolve(name, kind, &why);
  if (path.empty()) throw BadRequest(why, 403);
  return path;
}

// A seed beyond 2^53 does not survive a JSON number: it may come as a string.
uint64_t read_seed(SettingsReader& r, uint64_t fallback) {
  if (const Json* sd = r.json().get("seed"); sd && sd->type == Json::Type::String) {
    const std::string& t = sd->string;
    errno = 0;
    char* end = nullptr;
    const unsigned long long v = std::strtoull(t.c_str(), &end, 10);
    if (t.empty() || t.size() > 20 || t.find_first_not_of("0123456789") != std::string::npos || errno == ERANGE ||
        *end != '\0')
      throw BadRequest("seed: expected an integer from 0 to 18446744073709551615");
    return v;
  }
  return uint64_t(r.number("seed", 0, 9007199254740991.0, double(fallback), true));
}

// The cell render's rectangle, which must lie inside the image.
void read_cell(SettingsReader& r, RenderOptions& o) {
  const Json* c = r.json().get("cell");
  if (!c || c->type == Json::Type::Null) return;
  const std::vector<double> v = r.numbers("cell", r.json(), 4);
  for (double x : v)
    if (x != std::floor(x)) throw BadRequest("cell: expected 4 integers");
  if (v[0] < 0 || v[1] < 0 || v[2] < 1 || v[3] < 1 || v[0] + v[2] > o.width || v[1] + v[3] > o.height)
    throw BadRequest("cell: must lie inside the " + std::to_string(o.width) + "x" + std::to_string(o.height) +
                     " image and be at least 1x1");
  o.cell_set = true;
  o.cell_x = int(v[0]);
  o.cell_y = int(v[1]);
  o.cell_w = int(v[2]);
  o.cell_h = int(v[3]);
}

// The page's orbit: position, target and up.
CameraOverride read_camera(SettingsReader& r) {
  CameraOverride cam;
  const Json* c = r.json().get("camera");
  if (!c || c->type == Json::Type::Null) return cam;
  if (c->type != Json::Type::Object) throw BadRequest("camera: expected an object");
  const auto p = r.numbers("position", *c, 3), t = r.numbers("target", *c, 3), u = r.numbers("up", *c, 3);
  cam.set = true;
  cam.position = Vec3d(p[0], p[1], p[2]);
  cam.target = Vec3d(t[0], t[1], t[2]);
  cam.up = Vec3d(u[0], u[1], u[2]);
  if (!(norm(cam.position - cam.target) > 1e-9)) throw BadRequest("camera: position and target coincide");
  if (!(norm(cam.up) > 1e-9)) throw BadRequest("camera: up is zero");
  return cam;
}

// The numeric and boolean settings, with the command line's ranges.
void read_numbers(SettingsReader& r, const RenderOptions& start, RenderOptions& o) {
  o.part = int(r.number("part", 1, kPartsBuilt, start.part, true));
  o.samples_per_pixel = int(r.number("samples", 1, 1 << 20, start.samples_per_pixel, true));
  o.light_samples = int(r.number("light_samples", 1, 1 << 16, start.light_samples, true));
  o.max_depth = int(r.number("max_depth", 0, 1 << 20, start.max_depth, true));
  o.accumulate_bounces = r.flag("accumulate", start.accumulate_bounces);
  o.hemisphere_sampling = r.flag("hemisphere", start.hemisphere_sampling);
  o.threads = int(r.number("threads", 1, 256, start.threads, true));
  o.adaptive_batch = int(r.number("adaptive_batch", 1, 1 << 20, start.adaptive_batch, true));
  o.adaptive_tolerance = r.number("adaptive_tolerance", 1e-9, 1e9, start.adaptive_tolerance, false);
  o.adaptive_set = true;
  const double lens = r.number("lens_radius", 0, 1e6, start.lens_radius_set ? start.lens_radius : -1, false);
  o.lens_radius_set = lens >= 0;
  if (o.lens_radius_set) o.lens_radius = lens;
  const double focal = r.number("focal_distance", 1e-6, 1e9, start.focal_distance_set ? start.focal_distance : -1, false);
  o.focal_distance_set = focal > 0;
  if (o.focal_distance_set) o.focal_distance = focal;
  o.width = int(r.number("width", 1, 16384, start.width, true));
  o.height = int(r.number("height", 1, 16384, start.height, true));
  if ((long long)o.width * o.height > kMaxImagePixels)
    throw BadRequest("width x height: at most " + std::to_string(kMaxImagePixels) + " pixels");
  o.seed = read_seed(r, start.seed);
  o.bvh_max_leaf = int(r.number("bvh_leaf", 1, 255, start.bvh_max_leaf, true));
  o.bvh_bins = int(r.number("bvh_bins", 2, 64, start.bvh_bins, true));
}

}  // namespace

Request read_request(const Json& j, const RenderOptions& start, const FileAccess& files) {
  if (j.type != Json::Type::Object) throw BadRequest("expected a JSON object");
  SettingsReader r(j);
  Request q;
  RenderOptions& o = q.opts;
  o = start;
  o.output_png.clear();
  o.output_pfm.clear();
  o.stats_json.clear();
  o.cell_set = false;
  o.scene_path = read_file_setting(r, "scene", start.scene_path, FileKind::Scene, files, false);
  o.camera_settings = read_file_setting(r, "camera_file", start.camera_settings, FileKind::Camera, files, true);
  o.env_map = read_file_setting(r, "env", start.env_map, FileKind::Environment, files, true);
  read_numbers(r, start, o);
  read_cell(r, o);
  q.camera = read_camera(r);
  return q;
}

std::vector<std::string> render_flags(const RenderOptions& o) {
  std::vector<std::string> a = {"--part", std::to_string(o.part),
                                "-s", std::to_string(o.samples_per_pixel),
                                "-l", std::to_string(o.light_samples),
                                "-m", std::to_string(o.max_depth),
                                "-o", o.accumulate_bounces ? "1" : "0",
                                "-t", std::to_string(o.threads),
                                "-r", std::to_string(o.width), std::to_string(o.height),
                                "--seed", std::to_string(o.seed),
                                "--bvh-leaf", std::to_string(o.bvh_max_leaf),
                                "--bvh-bins", std::to_string(o.bvh_bins)};
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", o.adaptive_tolerance);
  a.insert(a.end(), {"-a", std::to_string(o.adaptive_batch), buf});
  if (o.hemisphere_sampling) a.push_back("-H");
  if (o.lens_radius_set) {
    std::snprintf(buf, sizeof buf, "%.17g", o.lens_radius);
    a.insert(a.end(), {"-b", buf});
  }
  if (o.focal_distance_set) {
    std::snprintf(buf, sizeof buf, "%.17g", o.focal_distance);
    a.insert(a.end(), {"-d", buf});
  }
  if (!o.camera_settings.empty()) a.insert(a.end(), {"-c", o.camera_settings});
  if (!o.env_map.empty()) a.insert(a.end(), {"-e", o.env_map});
  if (o.cell_set)
    a.insert(a.end(), {"-p", std::to_string(o.cell_x), std::to_string(o.cell_y), std::to_string(o.cell_w),
                       std::to_string(o.cell_h)});
  if (!o.russian_roulette) a.push_back("--no-rr");
  if (o.direct_only) a.push_back("--direct-only");
  if (o.indirect_only) a.push_back("--indirect-only");
  if (o.course_area_pdf) a.push_back("--course-area-pdf");
  a.push_back("--no-progress");
  a.push_back(o.scene_path);
  return a;
}

std::string settings_json(const RenderOptions& o) {
  std::ostringstream s;
  s << "{\"scene\":" << json_quote(o.scene_path) << ",\"part\":" << o.part << ",\"samples\":" << o.samples_per_pixel
    << ",\"light_samples\":" << o.light_samples << ",\"max_depth\":" << o.max_depth
    << ",\"accumulate\":" << (o.accumulate_bounces ? "true" : "false")
    << ",\"hemisphere\":" << (o.hemisphere_sampling ? "true" : "false") << ",\"threads\":" << o.threads
    << ",\"adaptive_batch\":" << o.adaptive_batch << ",\"adaptive_tolerance\":" << num(o.adaptive_tolerance)
    << ",\"lens_radius\":" << (o.lens_radius_set ? num(o.lens_radius) : "null")
    << ",\"focal_distance\":" << (o.focal_distance_set ? num(o.focal_distance) : "null")
    << ",\"width\":" << o.width << ",\"height\":" << o.height << ",\"seed\":"
    << (o.seed > 9007199254740991ull ? json_quote(std::to_string(o.seed)) : std::to_string(o.seed))
    << ",\"bvh_leaf\":" << o.bvh_max_leaf << ",\"bvh_bins\":" << o.bvh_bins
    << ",\"camera_file\":" << json_quote(o.camera_settings) << ",\"env\":" << json_quote(o.env_map) << ",\"cell\":";
  if (o.cell_set)
    s << "[" << o.cell_x << "," << o.cell_y << "," << o.cell_w << "," << o.cell_h << "]";
  else
    s << "null";
  s << "}";
  return s.str();
}

std::string vec_json(const Vec3d& v) { return "[" + num(v.x) + "," + num(v.y) + "," + num(v.z) + "]"; }

}  // namespace pt::viewer
