// Scenes as the page's 3D views see them: read by the server itself (the
// loader is given code, not a part's), the camera a render of a request
// uses, and the scene's geometry in the binary form /api/mesh sends.
#pragma once
#include <memory>
#include <mutex>
#include <string>

#include "common/camera.h"
#include "viewer/requests.h"
#include "common/scene.h"

namespace pt::viewer {

// The last scene read, kept for the next request on the same file.
class SceneCache {
 public:
  std::shared_ptr<const Scene> get(const std::string& path);

 private:
  std::mutex mu_;
  std::string path_;
  std::shared_ptr<const Scene> scene_;
};

// The camera a render of `q` uses: the scene's, with -r, -c, -b, -d, then
// the page's orbit when it sent one.
Camera request_camera(const Scene& scene, const Request& q);

// The scene's camera with only the settings applied (no orbit).
Camera default_camera(const Scene& scene, const RenderOptions& opts);

std::string camera_json(const Camera& c);

// uint32 triangles, uint32 spheres, then 9 floats per triangle (its
// corners), 9 per triangle (its vertex normals, the shading normals),
// 4 (centre, radius) per sphere, and an RGB byte triple per triangle
// and per sphere: the material's colour (emission scaled to 1, else
// the diffuse albedo).
std::string mesh_bytes(const Scene& scene);

}  // namespace pt::viewer
