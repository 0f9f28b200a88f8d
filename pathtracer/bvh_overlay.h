// BVH boxes drawn over a render, for write-up figures (--bvh-boxes,
// --bvh-node): the boxes of the BVH the render was traced with, as wire
// lines projected through the render's camera, in the viewer's BVH-mode
// colours.
#pragma once
#include <string>

#include "stages/part2_bvh/bvh.h"
#include "common/camera.h"
#include "common/image.h"

namespace pt {

// The viewer's colours, as 8-bit sRGB-like bytes of the course's curve.
struct OverlayColor {
  unsigned char r, g, b;
};
constexpr OverlayColor kDepthBoxColor{0xe6, 0xd8, 0x4a};  // every box at one depth: yellow
constexpr OverlayColor kNodeBoxColor{0xff, 0xff, 0xff};   // the chosen node: white
constexpr OverlayColor kLeftBoxColor{0xff, 0x4d, 0x4d};   // its left child: red
constexpr OverlayColor kRightBoxColor{0x4d, 0xa6, 0xff};  // its right child: blue

// The radiance whose 8-bit value (radiance_to_byte) is `byte`.
float radiance_for_byte(unsigned char byte);

// Draws the twelve edges of `box` into `img` (rows from the bottom, as the
// renderer fills it) as seen by `cam`, clipped to the near plane and to the
// image, `width` pixels wide, in `color`. No depth test: boxes behind
// surfaces show, as in the viewer.
void draw_box_edges(ImageBuffer& img, const Camera& cam, const BBox& box, OverlayColor color, int width = 1);

// What to draw: depth >= 0 draws every node at that depth (root 0); node >= 0
// draws that node (the viewer's numbering: the index into BVH::nodes()) and
// its two children over it. A depth the tree does not reach, or a node it
// does not have, draws nothing and says so in *note (empty otherwise).
void draw_bvh_overlay(ImageBuffer& img, const Camera& cam, const BVH& bvh, int depth, long long node,
                      std::string* note);

}  // namespace pt
