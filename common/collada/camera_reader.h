// The scene's camera: the first <instance_camera>'s perspective optics
// (field of view, aspect ratio, clipping) and view direction, placed after
// the walk from the bounds of all geometry by the course's rule, or the
// documented fallback when the scene has no camera.
#pragma once
#include "common/collada/document.h"
#include "common/mat4.h"
#include "common/collada/messages.h"
#include "common/scene.h"

namespace pt::collada {

class CameraReader {
 public:
  CameraReader(Messages& msg, const Document& doc) : msg_(msg), doc_(doc) {}

  // Reads the camera `inst` places with the node transform `world` when it
  // is the first one met (its clipping goes into `camera`); a later one is
  // only resolved.
  void add(const XMLElement* inst, const Mat4& world, Camera& camera);

  // Fits the field of view and places the camera; call once all geometry
  // is in `scene`. Problems are reported on `vscene`.
  void finish(const XMLElement* vscene, Scene& scene);

 private:
  // What a <perspective> gives; the fields without their flag are unset.
  struct FieldOfView {
    double xfov = 0, yfov = 0, aspect = 0;
    bool has_x = false, has_y = false, has_aspect = false;
  };
  void read_perspective(const XMLElement* persp, FieldOfView& fov, Camera& camera);
  void complete(const XMLElement* e, FieldOfView fov);
  void read_direction(const XMLElement* inst, const Mat4& world);

  Messages& msg_;
  const Document& doc_;
  bool have_camera_ = false;
  double xfov_ = 0, yfov_ = 0;  // full fields of view, degrees
  Vec3d camera_dir_{0, 0, 1};   // from the scene's centre toward the camera
};

}  // namespace pt::collada
