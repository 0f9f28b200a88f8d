// The node walk: the chosen <visual_scene> visited depth-first in document
// order with the accumulated world transform (each node's <matrix>,
// <translate>, <rotate>, <scale> and <lookat> composed in order), library
// nodes entered through <instance_node>, and each geometry, light and
// camera handed to its reader as it is met. Guards against cycles, deep
// nesting and exponential instancing.
#pragma once
#include <vector>

#include "common/collada/camera_reader.h"
#include "common/collada/document.h"
#include "common/collada/geometry_reader.h"
#include "common/mat4.h"
#include "common/collada/messages.h"
#include "common/scene.h"

namespace pt::collada {

class NodeWalk {
 public:
  NodeWalk(Messages& msg, const Document& doc, GeometryReader& geometry, CameraReader& camera, Scene& scene)
      : msg_(msg), doc_(doc), geometry_(geometry), camera_(camera), scene_(scene) {}

  // Visits the contents of `vscene` (a <visual_scene>) under `up_axis`.
  void walk(const XMLElement* vscene, const Mat4& up_axis) { visit_children(vscene, up_axis, 0); }

 private:
  Mat4 local_transform(const XMLElement* node);
  Mat4 matrix(const XMLElement* e);
  Mat4 lookat(const XMLElement* e) const;
  void visit_node(const XMLElement* node, const Mat4& parent, int depth);
  void visit_children(const XMLElement* node, const Mat4& world, int depth);
  void visit_instance_node(const XMLElement* inst, const Mat4& world, int depth);

  Messages& msg_;
  const Document& doc_;
  GeometryReader& geometry_;
  CameraReader& camera_;
  Scene& scene_;
  std::vector<const XMLElement*> instancing_;  // nodes entered through <instance_node>
  long instances_ = 0;                         // nodes and instance_* elements visited
};

}  // namespace pt::collada
