// π, defined once for the whole project: in double for angles and the
// scene's geometry (degrees to radians in the camera and the scene loader),
// in float for the shading code. Named math_constants.h, not math.h: a
// math.h here would hide the C library's <math.h> from every file built
// with this folder on its path.
#pragma once

namespace pt {

constexpr double kPiDouble = 3.14159265358979323846;
constexpr float kPi = float(kPiDouble);  // the float nearest π
constexpr float kInvPi = 1.0f / kPi;
constexpr float kInv2Pi = 1.0f / (2.0f * kPi);

}  // namespace pt
