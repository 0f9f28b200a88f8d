// A render as the page asks for it: the JSON settings it sends, read and
// checked the way the command line checks its flags, into RenderOptions
// (and the page's orbit camera); and back, the flags that make the command
// line (or a worker) render the same image, and the settings as JSON.
#pragma once
#include <stdexcept>
#include <string>
#include <vector>

#include "viewer/file_access.h"
#include "common/json.h"
#include "pathtracer/options.h"
#include "common/vec3.h"

namespace pt::viewer {

// A bad request: the message goes to the page with status 400 (or `status`).
struct BadRequest : std::runtime_error {
  int status;
  explicit BadRequest(const std::string& m, int s = 400) : std::runtime_error(m), status(s) {}
};


// The page's orbit, when it sent one.
struct CameraOverride {
  bool set = false;
  Vec3d position, target, up;
};

// The render the page asks for, as options and as the worker's flags.
struct Request {
  RenderOptions opts;
  CameraOverride camera;
};

// Reads the page's settings over `start` (the command line's); the files
// it names must be ones `files` allows (403 otherwise).
Request read_request(const Json& j, const RenderOptions& start, const FileAccess& files);

// The flags that make the command line render `o` (no output files).
std::vector<std::string> render_flags(const RenderOptions& o);

// `o` as the page's settings object (the members read_request reads).
std::string settings_json(const RenderOptions& o);

std::string vec_json(const Vec3d& v);

}  // namespace pt::viewer
