// π, defined once: in double for the scene's geometry and camera (which
// work in double), in float for the shading code (which works in float).
// Named math_constants.h, not math.h: a math.h here would hide the C
// library's <math.h> from every file built with this folder on its path.
#pragma once

namespace pt {

constexpr double kPiDouble = 3.14159265358979323846;
constexpr float kPi = float(kPiDouble);  // the float nearest π

}  // namespace pt
