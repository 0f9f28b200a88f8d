// The node walk (see node_walk.h).
#include "common/collada/node_walk.h"

#include <cmath>
#include <cstring>
#include <string>

#include "common/collada/light_reader.h"
#include "common/collada/xml_values.h"

namespace pt::collada {

namespace {

constexpr int kMaxNodeDepth = 256;       // nested <node>/<instance_node> levels
constexpr long kMaxInstances = 1000000;  // nodes and instance_* visited: guards against exponential instancing

}  // namespace

// A <matrix>: 16 finite numbers, row by row, the last row 0 0 0 1.
Mat4 NodeWalk::matrix(const XMLElement* c) {
  std::vector<double> v = numbers(msg_, c);
  if (v.size() > 16) msg_.fail(c, "expected 16 numbers (a 4x4 matrix, row by row), found " + std::to_string(v.size()));
  for (double x : v)
    if (!std::isfinite(x)) msg_.fail(c, "contains a number that is not finite");
  if (v.size() < 16) {
    // The course reads missing numbers as 0 and some of its files rely
    // on it (CBgems.dae's camera has 15). The bottom row cannot be
    // right after such a fill; a transform needs 0 0 0 1 there.
    msg_.warn_once(c, "has " + std::to_string(v.size()) +
                          " numbers instead of 16; the missing ones are read as 0, as the course reads them, "
                          "and the bottom row as 0 0 0 1");
    v.resize(16, 0.0);
    v[15] = 1;
  } else if (v[12] != 0 || v[13] != 0 || v[14] != 0 || v[15] != 1) {
    msg_.fail(c, "the last row must be 0 0 0 1 (projective transforms are not supported)");
  }
  return Mat4::from_row_major(v.data());
}

// A <lookat>: the frame at the eye whose -z looks at the interest point.
Mat4 NodeWalk::lookat(const XMLElement* c) const {
  const std::vector<double> v = numbers(msg_, c, 9, "eye, interest point and up vector");
  const Vec3d eye(v[0], v[1], v[2]), at(v[3], v[4], v[5]), up(v[6], v[7], v[8]);
  const Vec3d back = eye - at;
  if (norm2(back) == 0) msg_.fail(c, "the eye and the interest point are the same point");
  const Vec3d z = normalize(back);
  const Vec3d xc = cross(up, z);
  if (!(norm(xc) > 1e-12 * norm(up))) msg_.fail(c, "the up vector is zero or parallel to the view direction");
  const Vec3d x = normalize(xc), y = cross(z, x);
  Mat4 l;
  for (int i = 0; i < 3; ++i) {
    l.m[i][0] = x[i];
    l.m[i][1] = y[i];
    l.m[i][2] = z[i];
    l.m[i][3] = eye[i];
  }
  return l;
}

// The node's own transform: its transform elements composed in document
// order, M = T1 * T2 * ... (the last one applies to the geometry first).
Mat4 NodeWalk::local_transform(const XMLElement* node) {
  Mat4 m;
  for (const XMLElement* c = node->FirstChildElement(); c; c = c->NextSiblingElement()) {
    const char* name = c->Name();
    if (std::strcmp(name, "matrix") == 0) {
      m = m * matrix(c);
    } else if (std::strcmp(name, "translate") == 0) {
      const std::vector<double> v = numbers(msg_, c, 3, "x y z");
      m = m * Mat4::translate({v[0], v[1], v[2]});
    } else if (std::strcmp(name, "scale") == 0) {
      const std::vector<double> v = numbers(msg_, c, 3, "x y z");
      m = m * Mat4::scale({v[0], v[1], v[2]});
    } else if (std::strcmp(name, "rotate") == 0) {
      const std::vector<double> v = numbers(msg_, c, 4, "axis x y z, angle in degrees");
      const Vec3d axis(v[0], v[1], v[2]);
      if (norm2(axis) == 0) msg_.fail(c, "the rotation axis is the zero vector");
      m = m * Mat4::rotate(axis, v[3]);
    } else if (std::strcmp(name, "lookat") == 0) {
      m = m * lookat(c);
    } else if (std::strcmp(name, "skew") == 0) {
      msg_.fail(c, "<skew> transforms are not supported");
    }
  }
  return m;
}

void NodeWalk::visit_node(const XMLElement* node, const Mat4& parent, int depth) {
  if (depth > kMaxNodeDepth) msg_.fail(node, "nodes are nested more than " + std::to_string(kMaxNodeDepth) + " deep");
  visit_children(node, parent * local_transform(node), depth);
}

void NodeWalk::visit_instance_node(const XMLElement* inst, const Mat4& world, int depth) {
  const XMLElement* target = doc_.resolve(inst, "url", "node");
  for (const XMLElement* active : instancing_)
    if (active == target) msg_.fail(inst, "instance_node creates a cycle (the node contains itself)");
  instancing_.push_back(target);
  visit_node(target, world, depth + 1);
  instancing_.pop_back();
}

// Visits the contents of a node (or of a <visual_scene>) in document order.
void NodeWalk::visit_children(const XMLElement* node, const Mat4& world, int depth) {
  if (std::strcmp(node->Name(), "node") == 0)
    msg_.check_children(node, {"asset", "lookat", "matrix", "rotate", "scale", "skew", "translate",
                               "instance_camera", "instance_controller", "instance_geometry", "instance_light",
                               "instance_node", "node", "extra"});
  else
    msg_.check_children(node, {"asset", "node", "evaluate_scene", "extra"});
  for (const XMLElement* c = node->FirstChildElement(); c; c = c->NextSiblingElement()) {
    const char* name = c->Name();
    if (std::strncmp(name, "instance_", 9) == 0 || std::strcmp(name, "node") == 0)
      if (++instances_ > kMaxInstances)
        msg_.fail(c, "more than " + std::to_string(kMaxInstances) + " nodes and instances; the scene is too large");
    if (std::strcmp(name, "node") == 0) {
      visit_node(c, world, depth + 1);
    } else if (std::strcmp(name, "instance_node") == 0) {
      visit_instance_node(c, world, depth);
    } else if (std::strcmp(name, "instance_geometry") == 0) {
      geometry_.add(c, world);
    } else if (std::strcmp(name, "instance_light") == 0) {
      if (const auto light = read_light(msg_, doc_, c, world)) scene_.lights.push_back(*light);
    } else if (std::strcmp(name, "instance_camera") == 0) {
      camera_.add(c, world, scene_.camera);
    } else if (std::strcmp(name, "instance_controller") == 0) {
      msg_.warn(c, "controllers (skinning, morphing) are not supported; skipped");
    }
  }
}

}  // namespace pt::collada
