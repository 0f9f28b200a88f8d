#include "pathtracer/bvh_overlay.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/image_io.h"

namespace pt {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Clips the segment a + t (b - a), t in [t0, t1], to p(t) <= q(t) style
// half-spaces given as (p, q): keeps t with p * t <= q. Liang-Barsky.
bool clip(double p, double q, double* t0, double* t1) {
  if (p == 0) return q >= 0;
  const double r = q / p;
  if (p < 0) {
    if (r > *t1) return false;
    *t0 = std::max(*t0, r);
  } else {
    if (r < *t0) return false;
    *t1 = std::min(*t1, r);
  }
  return true;
}

void plot(ImageBuffer& img, int x, int y, const Color& c, int width) {
  const int lo = -(width - 1) / 2, hi = width / 2;
  for (int dy = lo; dy <= hi; ++dy)
    for (int dx = lo; dx <= hi; ++dx) {
      const int px = x + dx, py = y + dy;
      if (px >= 0 && py >= 0 && px < img.width && py < img.height) img.at(px, py) = c;
    }
}

}  // namespace

float radiance_for_byte(unsigned char byte) {
  // radiance_to_byte is floor(255 (sqrt(2) L)^(1/2.2)): aim at the middle
  // of the byte's interval, then make sure of it.
  float L = float(std::pow((byte + 0.5) / 255.0, 2.2) / std::sqrt(2.0));
  if (byte == 255) L = 1.0f;
  while (radiance_to_byte(L) > byte) L = std::nextafter(L, 0.0f);
  while (radiance_to_byte(L) < byte) L = std::nextafter(L, 2.0f);
  return L;
}

void draw_box_edges(ImageBuffer& img, const Camera& cam, const BBox& box, OverlayColor color, int width) {
  if (box.empty()) return;
  const Color c(radiance_for_byte(color.r), radiance_for_byte(color.g), radiance_for_byte(color.b));
  const double tan_h = std::tan(0.5 * cam.hfov_deg * kPi / 180.0);
  const double tan_v = std::tan(0.5 * cam.vfov_deg * kPi / 180.0);
  const double near = std::max(cam.near_clip, 1e-6);
  // The corners in camera space: x right, y up, z the distance in front.
  Vec3d corner[8];
  for (int k = 0; k < 8; ++k) {
    const Vec3d p(k & 1 ? box.hi.x : box.lo.x, k & 2 ? box.hi.y : box.lo.y, k & 4 ? box.hi.z : box.lo.z);
    const Vec3d d = p - cam.position;
    corner[k] = Vec3d(dot(d, cam.axis_x), dot(d, cam.axis_y), -dot(d, cam.axis_z));
  }
  static const int kEdges[12][2] = {{0, 1}, {1, 3}, {3, 2}, {2, 0}, {4, 5}, {5, 7},
                                    {7, 6}, {6, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  for (const auto& e : kEdges) {
    Vec3d a = corner[e[0]], b = corner[e[1]];
    // In front of the near plane only.
    if (a.z < near && b.z < near) continue;
    if (a.z < near) a = a + (b - a) * ((near - a.z) / (b.z - a.z));
    if (b.z < near) b = b + (a - b) * ((near - b.z) / (a.z - b.z));
    // Image coordinates: pixel (x, y) covers [x, x + 1) x [y, y + 1), rows
    // from the bottom, as generate_ray maps them.
    const auto to_image = [&](const Vec3d& p, double* x, double* y) {
      *x = (p.x / (p.z * tan_h) + 1.0) * 0.5 * img.width;
      *y = (p.y / (p.z * tan_v) + 1.0) * 0.5 * img.height;
    };
    double x0, y0, x1, y1;
    to_image(a, &x0, &y0);
    to_image(b, &x1, &y1);
    const double dx = x1 - x0, dy = y1 - y0;
    double t0 = 0, t1 = 1;
    const double m = width + 1.0;
    if (!clip(-dx, x0 + m, &t0, &t1) || !clip(dx, img.width + m - x0, &t0, &t1) || !clip(-dy, y0 + m, &t0, &t1) ||
        !clip(dy, img.height + m - y0, &t0, &t1) || t0 > t1)
      continue;
    const double sx = x0 + t0 * dx, sy = y0 + t0 * dy, len = (t1 - t0) * std::max(std::abs(dx), std::abs(dy));
    const int steps = int(std::ceil(len)) + 1;
    for (int s = 0; s <= steps; ++s) {
      const double u = steps ? double(s) / steps : 0.0;
      plot(img, int(std::floor(sx + u * (t1 - t0) * dx)), int(std::floor(sy + u * (t1 - t0) * dy)), c, width);
    }
  }
}

void draw_bvh_overlay(ImageBuffer& img, const Camera& cam, const BVH& bvh, int depth, long long node,
                      std::string* note) {
  const std::vector<BVHNode>& nodes = bvh.nodes();
  const auto box_of = [&](size_t i) { return BBox(nodes[i].lo, nodes[i].hi); };
  // Node 1 is padding: children start at even indices.
  // A node or depth the tree does not have draws nothing, with a note: an
  // unfinished part 2 (a single leaf) still gets its image.
  if (node >= 0 && (size_t(node) >= nodes.size() || node == 1)) {
    const std::string which = nodes.empty()       ? "the BVH has no nodes"
                              : nodes.size() <= 2 ? "the BVH has only node 0"
                                                  : "the BVH has nodes 0 and 2 to " + std::to_string(nodes.size() - 1);
    if (note) *note = "--bvh-node " + std::to_string(node) + ": " + which + "; no boxes drawn";
    node = -1;
  }
  if (depth >= 0 && !nodes.empty()) {
    // Breadth first from the root, as the viewer numbers depths.
    std::vector<uint32_t> level = {0}, next;
    for (int d = 0; d < depth && !level.empty(); ++d) {
      next.clear();
      for (uint32_t i : level)
        if (!nodes[i].is_leaf()) next.insert(next.end(), {nodes[i].first, nodes[i].first + 1});
      level.swap(next);
    }
    if (level.empty() && note)
      *note = (note->empty() ? "" : *note + "; ") + "--bvh-boxes " + std::to_string(depth) + ": the BVH is only " +
              std::to_string(bvh.build_stats().depth) + " deep; no boxes drawn";
    for (uint32_t i : level) draw_box_edges(img, cam, box_of(i), kDepthBoxColor, 1);
  } else if (depth >= 0 && note) {
    *note = (note->empty() ? "" : *note + "; ") + "--bvh-boxes " + std::to_string(depth) +
            ": the BVH is empty; no boxes drawn";
  }
  if (node >= 0) {
    // In the viewer's order: the node, then its children over it.
    const BVHNode& n = nodes[size_t(node)];
    draw_box_edges(img, cam, box_of(size_t(node)), kNodeBoxColor, 2);
    if (!n.is_leaf()) {
      draw_box_edges(img, cam, box_of(n.first), kLeftBoxColor, 2);
      draw_box_edges(img, cam, box_of(n.first + 1), kRightBoxColor, 2);
    }
  }
}

}  // namespace pt
