// π, defined once for the whole project: in double precision for angles
// (degrees to radians in the camera and the scene loader), in single
// precision for the shading code.
#pragma once

namespace pt {

constexpr double kPiDouble = 3.14159265358979323846;
constexpr float kPi = float(kPiDouble);
constexpr float kInvPi = 1.0f / kPi;
constexpr float kInv2Pi = 1.0f / (2.0f * kPi);

}  // namespace pt
