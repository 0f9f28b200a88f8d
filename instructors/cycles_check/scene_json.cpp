// scene_json: the scene as this project's loader reads it, written as JSON
// for cycles_scene.py to build the same scene in Blender's Cycles.
//
//   scene_json SCENE.dae WIDTH HEIGHT OUT.json [-e MAP.exr] [-b RADIUS] [-d DISTANCE]
//
// Everything is in the renderer's world space (Y up) after loading: the
// camera as a render of WIDTH x HEIGHT sets it up (fields of view for that
// size, -b and -d applied), every triangle with its vertex normals, every
// sphere, every material, every light. Exits 1 with one line naming the
// file on bad input; writes OUT.json only when everything was read.
#include <cmath>
#include <cstdio>
#include <exception>
#include <fstream>
#include <sstream>
#include <string>

#include "common/collada.h"
#include "common/json.h"
#include "common/scene.h"

namespace {

using pt::json_number;

std::string flat(const pt::Vec3& v);
std::string vec(const pt::Vec3& v) { return "[" + flat(v) + "]"; }
// "x,y,z": a vector's components inside a flat array.
std::string flat(const pt::Vec3& v) { return json_number(v.x) + "," + json_number(v.y) + "," + json_number(v.z); }
std::string vecd(const pt::Vec3d& v) {
  return "[" + json_number(v.x) + "," + json_number(v.y) + "," + json_number(v.z) + "]";
}

std::string material_json(const pt::Material& m) {
  std::ostringstream o;
  o << "{\"name\":" << pt::json_quote(m.name) << ",\"type\":" << pt::json_quote(pt::to_string(m.type))
    << ",\"albedo\":" << vec(m.albedo) << ",\"emission\":" << vec(m.emission)
    << ",\"reflectance\":" << vec(m.reflectance) << ",\"transmittance\":" << vec(m.transmittance)
    << ",\"roughness\":" << json_number(m.roughness) << ",\"ior\":" << json_number(m.ior)
    << ",\"alpha\":" << json_number(m.alpha) << ",\"eta\":" << vec(m.eta) << ",\"k\":" << vec(m.k) << "}";
  return o.str();
}

std::string light_json(const pt::Light& l) {
  std::ostringstream o;
  o << "{\"type\":" << pt::json_quote(pt::to_string(l.type)) << ",\"radiance\":" << vec(l.radiance)
    << ",\"position\":" << vec(l.position) << ",\"direction\":" << vec(l.direction) << ",\"dim_x\":" << vec(l.dim_x)
    << ",\"dim_y\":" << vec(l.dim_y) << ",\"attenuation\":[" << json_number(l.constant_attenuation) << ","
    << json_number(l.linear_attenuation) << "," << json_number(l.quadratic_attenuation) << "]}";
  return o.str();
}

double number(const std::string& text, const std::string& what) {
  size_t used = 0;
  double v = 0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || !std::isfinite(v)) throw std::runtime_error(what + " must be a number, not '" + text + "'");
  return v;
}

int run(int argc, char** argv) {
  if (argc < 5) {
    std::fprintf(stderr, "usage: scene_json SCENE.dae WIDTH HEIGHT OUT.json [-e MAP.exr] [-b RADIUS] [-d DISTANCE]\n");
    return 2;
  }
  const std::string scene_path = argv[1], out_path = argv[4];
  const double w = number(argv[2], "WIDTH"), h = number(argv[3], "HEIGHT");
  if (w < 1 || h < 1 || w > 65536 || h > 65536 || w != int(w) || h != int(h))
    throw std::runtime_error("WIDTH and HEIGHT must be whole numbers from 1 to 65536");
  const int width = int(w), height = int(h);
  std::string env;
  double lens = -1, focal = -1;
  if ((argc - 5) % 2 != 0) throw std::runtime_error(std::string("option ") + argv[argc - 1] + " needs a value");
  for (int i = 5; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "-e") env = argv[i + 1];
    else if (flag == "-b") lens = number(argv[i + 1], "-b");
    else if (flag == "-d") focal = number(argv[i + 1], "-d");
    else throw std::runtime_error("unknown option " + flag);
  }
  pt::Scene scene = pt::load_collada(scene_path);
  pt::Camera& cam = scene.camera;
  cam.set_resolution(width, height);
  if (lens >= 0) cam.lens_radius = lens;
  if (focal > 0) cam.focal_distance = focal;

  std::ostringstream o;
  o << "{\"source\":" << pt::json_quote(scene_path) << ",\"width\":" << width << ",\"height\":" << height
    << ",\"environment_map\":" << (env.empty() ? std::string("null") : pt::json_quote(env)) << ",\n\"camera\":{"
    << "\"position\":" << vecd(cam.position) << ",\"axis_x\":" << vecd(cam.axis_x) << ",\"axis_y\":"
    << vecd(cam.axis_y) << ",\"axis_z\":" << vecd(cam.axis_z) << ",\"hfov_deg\":" << json_number(cam.hfov_deg)
    << ",\"vfov_deg\":" << json_number(cam.vfov_deg) << ",\"near_clip\":" << json_number(cam.near_clip)
    << ",\"far_clip\":" << json_number(cam.far_clip) << ",\"lens_radius\":" << json_number(cam.lens_radius)
    << ",\"focal_distance\":" << json_number(cam.focal_distance) << "},\n\"materials\":[";
  for (size_t i = 0; i < scene.materials.size(); ++i) o << (i ? ",\n" : "\n") << material_json(scene.materials[i]);
  o << "],\n\"lights\":[";
  for (size_t i = 0; i < scene.lights.size(); ++i) o << (i ? ",\n" : "\n") << light_json(scene.lights[i]);
  o << "],\n\"spheres\":[";
  for (size_t i = 0; i < scene.spheres.size(); ++i) {
    const pt::Sphere& s = scene.spheres[i];
    o << (i ? ",\n" : "\n") << "{\"center\":" << vec(s.center) << ",\"radius\":" << json_number(s.radius)
      << ",\"material\":" << s.material << "}";
  }
  // Triangles as flat arrays: 9 positions, 9 normals and a material each.
  o << "],\n\"triangles\":{\"positions\":[";
  for (size_t i = 0; i < scene.triangles.size(); ++i) {
    const pt::Triangle& t = scene.triangles[i];
    o << (i ? ",\n" : "\n") << flat(t.p1) << "," << flat(t.p2) << "," << flat(t.p3);
  }
  o << "],\n\"normals\":[";
  for (size_t i = 0; i < scene.triangles.size(); ++i) {
    const pt::Triangle& t = scene.triangles[i];
    o << (i ? ",\n" : "\n") << flat(t.n1) << "," << flat(t.n2) << "," << flat(t.n3);
  }
  o << "],\n\"materials\":[";
  for (size_t i = 0; i < scene.triangles.size(); ++i) o << (i ? "," : "") << scene.triangles[i].material;
  o << "]}}\n";

  const std::string tmp = out_path + ".partial";
  {
    std::ofstream f(tmp, std::ios::binary);
    f << o.str();
    if (!f) throw std::runtime_error(out_path + ": cannot write");
  }
  if (std::rename(tmp.c_str(), out_path.c_str()) != 0) throw std::runtime_error(out_path + ": cannot write");
  std::printf("%s: %zu triangles, %zu spheres, %zu materials, %zu lights\n", out_path.c_str(), scene.triangles.size(),
              scene.spheres.size(), scene.materials.size(), scene.lights.size());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "scene_json: %s\n", e.what());
    return 1;
  }
}
