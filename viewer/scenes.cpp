#include "viewer/scenes.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "common/collada.h"
#include "pathtracer/render_job.h"

namespace pt::viewer {

namespace {

std::string num(double v) { return pt::json_number(v); }

// A material's colour for the preview, as 8-bit RGB.
void append_colour(const Scene& scene, int material, std::string* colours) {
  Color c(0.5f);
  if (material >= 0 && size_t(material) < scene.materials.size()) {
    const Material& m = scene.materials[size_t(material)];
    if (m.is_emissive()) {
      const float k = std::max({m.emission.x, m.emission.y, m.emission.z});
      c = m.emission / k;
    } else {
      c = m.albedo;
    }
  }
  for (int ch = 0; ch < 3; ++ch) colours->push_back(char(std::lround(255 * std::clamp(c[ch], 0.0f, 1.0f))));
}

}  // namespace

std::shared_ptr<const Scene> SceneCache::get(const std::string& path) {
  std::lock_guard<std::mutex> lock(mu_);
  if (scene_ && path_ == path) return scene_;
  auto s = std::make_shared<Scene>(load_collada(path));
  path_ = path;
  scene_ = s;
  return s;
}

Camera request_camera(const Scene& scene, const Request& q) {
  Camera cam = scene.camera;
  configure_camera(cam, q.opts);
  if (q.camera.set) cam.look_at(q.camera.position, q.camera.target, q.camera.up);
  return cam;
}

Camera default_camera(const Scene& scene, const RenderOptions& opts) {
  Camera d = scene.camera;
  configure_camera(d, opts);
  return d;
}

std::string camera_json(const Camera& c) {
  return "{\"position\":" + vec_json(c.position) + ",\"target\":" + vec_json(c.target) +
         ",\"axis_x\":" + vec_json(c.axis_x) + ",\"axis_y\":" + vec_json(c.axis_y) +
         ",\"axis_z\":" + vec_json(c.axis_z) + ",\"hfov\":" + num(c.hfov_deg) + ",\"vfov\":" + num(c.vfov_deg) +
         ",\"near\":" + num(c.near_clip) + ",\"far\":" + num(c.far_clip) + ",\"width\":" + std::to_string(c.width) +
         ",\"height\":" + std::to_string(c.height) + ",\"lens_radius\":" + num(c.lens_radius) +
         ",\"focal_distance\":" + num(c.focal_distance) + "}";
}

std::string mesh_bytes(const Scene& scene) {
  const uint32_t nt = uint32_t(scene.triangles.size()), ns = uint32_t(scene.spheres.size());
  std::string body(8 + size_t(nt) * 72 + size_t(ns) * 16, '\0');
  std::string colours;
  for (const Triangle& t : scene.triangles) append_colour(scene, t.material, &colours);
  for (const Sphere& sp : scene.spheres) append_colour(scene, sp.material, &colours);
  char* p = body.data();
  std::memcpy(p, &nt, 4);
  std::memcpy(p + 4, &ns, 4);
  p += 8;
  for (const Triangle& t : scene.triangles) {
    const float v[9] = {t.p1.x, t.p1.y, t.p1.z, t.p2.x, t.p2.y, t.p2.z, t.p3.x, t.p3.y, t.p3.z};
    std::memcpy(p, v, 36);
    p += 36;
  }
  for (const Triangle& t : scene.triangles) {
    const float n[9] = {t.n1.x, t.n1.y, t.n1.z, t.n2.x, t.n2.y, t.n2.z, t.n3.x, t.n3.y, t.n3.z};
    std::memcpy(p, n, 36);
    p += 36;
  }
  for (const Sphere& sp : scene.spheres) {
    const float v[4] = {sp.center.x, sp.center.y, sp.center.z, sp.radius};
    std::memcpy(p, v, 16);
    p += 16;
  }
  return body + colours;
}

}  // namespace pt::viewer
