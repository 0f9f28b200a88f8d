// Lights: an <instance_light>'s <light> (CGL technique, else
// technique_common) read into a world-space area, point, directional or
// ambient light. Spot and unknown lights are skipped with a warning.
#pragma once
#include <optional>

#include "common/collada/document.h"
#include "common/mat4.h"
#include "common/collada/messages.h"
#include "common/scene.h"

namespace pt::collada {

// The light `inst` places with the node transform `world`; none when it is
// skipped.
std::optional<Light> read_light(Messages& msg, const Document& doc, const XMLElement* inst, const Mat4& world);

}  // namespace pt::collada
