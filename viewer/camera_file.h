// The course's camera settings file (what -c reads), written from a camera.
#pragma once
#include <string>

#include "common/camera.h"

namespace pt::viewer {

// Six lines: hFov vFov ar nClip fClip / pos.xyz target.xyz /
// phi theta r minR maxR / camera-to-world 3x3, row-major /
// screenW screenH screenDist / focalDistance lensRadius. Numbers are
// written with 17 significant digits, so Camera::load_settings gives back
// this camera exactly.
std::string camera_settings_text(const Camera& cam);

}  // namespace pt::viewer
