// Environment maps (-e): an image of the radiance arriving from every
// direction at infinity, stored as a latitude-longitude (equirectangular)
// OpenEXR image.
//
// Direction convention (world space, Y up): theta = acos(d.y) runs from the
// top row (theta = 0, straight up) to the bottom row (theta = pi);
// phi = atan2(d.x, -d.z) in [-pi, pi) runs from the left column (phi = -pi)
// to the right; the image's centre column looks along -Z.
#pragma once
#include <string>
#include <vector>

#include "common/vec3.h"

namespace pt {

struct EnvironmentMap {
  int width = 0, height = 0;
  std::vector<Color> texels;  // row by row from the top

  // Radiance arriving from direction d (unit, pointing away from the scene),
  // nearest texel. A direction with NaN or infinite components still gives
  // a texel of the map.
  Color lookup(const Vec3& d) const;
};

// Reads an OpenEXR image's RGB channels. Throws std::runtime_error naming
// the file on a missing, unreadable or malformed file, or non-finite or
// negative texels. The header is checked before anything is allocated for
// the image: at most 33,554,432 texels (8192 x 4096) and tiles of at most
// 4,194,304; attributes that fit the file and match their types; pixel data
// that can fit the file at its compression's best ratio. Multi-part and
// deep files are refused.
EnvironmentMap load_environment_map(const std::string& path);

}  // namespace pt
