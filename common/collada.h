// Loading the course's COLLADA 1.4 scene files (with its CGL extensions)
// into the scene model. The conventions implemented here are stated in
// docs/scene-format.md.
#pragma once
#include <stdexcept>
#include <string>
#include <vector>

#include "common/scene.h"

namespace pt {

// A scene file that cannot be loaded. what() is one line of the form
// "<file>: <element>: <what is wrong>".
class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The most triangles and spheres a scene may have. Instancing can multiply
// a small file into a huge scene (a node placed 16 times, itself placed 16
// times, ...); loading stops with a SceneError when the count would pass
// this limit, before the memory for the excess is taken. It is 20 times the
// largest scene the project ships (200,014 triangles) and about 300 MB of
// triangles.
constexpr size_t kMaxScenePrimitives = 4000000;

// Loads `path`. Problems that still leave a usable scene (an unknown or spot
// light, degenerate triangles dropped, no camera, an element the loader does
// not know where it would lose content, a short <matrix>) are appended to
// `warnings` as one-line messages; anything else throws SceneError.
Scene load_collada(const std::string& path, std::vector<std::string>* warnings = nullptr);

}  // namespace pt
