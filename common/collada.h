// Loading the course's COLLADA 1.4 scene files (with its CGL extensions)
// into the scene model. The conventions implemented here are stated in
// docs/scene-format.md.
#pragma once
#include <stdexcept>
#include <string>
#include <vector>

#include "scene.h"

namespace pt {

// A scene file that cannot be loaded. what() is one line of the form
// "<file>: <element>: <what is wrong>".
class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Loads `path`. Problems that still leave a usable scene (an unknown or spot
// light, degenerate triangles dropped, no camera) are appended to `warnings`
// as one-line messages; anything else throws SceneError.
Scene load_collada(const std::string& path, std::vector<std::string>* warnings = nullptr);

}  // namespace pt
