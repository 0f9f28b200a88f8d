// Environment maps (-e): an image of the radiance arriving from every
// direction at infinity, stored as a latitude-longitude (equirectangular)
// OpenEXR image.
//
// Direction convention (world space, Y up), the course's: theta =
// acos(d.y) runs from the top row (theta = 0, straight up) to the bottom row
// (theta = pi); phi = atan2(-d.z, d.x) + pi in [0, 2 pi] runs from the left
// column to the right. The left and right edges look along -X, the centre
// column along +X, a quarter of the way across along +Z, three quarters
// along -Z.
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

  // The texel (column x, row y from the top) that direction d looks up.
  void texel_of(const Vec3& d, int* x, int* y) const;
};

// The angles of a unit direction (theta in [0, pi], phi in [0, 2 pi]), and
// the unit direction of two angles, by the convention above.
void direction_to_angles(const Vec3& d, float* theta, float* phi);
Vec3 angles_to_direction(float theta, float phi);

// Reads an OpenEXR image's RGB channels. Throws std::runtime_error naming
// the file on a missing, unreadable or malformed file, or non-finite or
// negative texels. The header is checked before anything is allocated for
// the image: at most 33,554,432 texels (8192 x 4096) and tiles of at most
// 4,194,304; attributes that fit the file and match their types; pixel data
// that can fit the file at its compression's best ratio. Multi-part and
// deep files are refused.
EnvironmentMap load_environment_map(const std::string& path);

}  // namespace pt
