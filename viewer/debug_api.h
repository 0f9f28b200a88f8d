// The viewer's Debug mode in the worker process: the page's input for one
// of the debugger's tools (viewer/debugger/debugger.h) read from JSON, the
// tool run on the build's own code, its result as JSON. The server starts
// a worker per call ("--worker debug TOOL INPUT flags... scene"), so that a
// crash in a part's code ends the worker, not the server.
#pragma once
#include <functional>
#include <string>

#include "pathtracer/options.h"
#include "common/scene.h"

namespace pt::viewer {

// The tools: "intersect" (a ray against a typed triangle or sphere, or a
// primitive of the scene), "lights" (many samples of one light from a
// point), "path" (one sample of one pixel replayed and recorded), "bsdf"
// (many samples of the BSDF at a pixel's first hit), "envmap" (where the
// -e map is sampled).
bool is_debug_tool(const std::string& tool);

// Runs `tool` on `input` (the page's JSON object) with the settings `opts`;
// `load` reads the scene with the camera configured for `opts`. Returns the
// result's JSON text. Absurd input throws pt::debug::InputError (also for
// malformed members of `input`).
std::string run_debug_tool(const std::string& tool, const std::string& input, const RenderOptions& opts,
                           const std::function<Scene()>& load);

}  // namespace pt::viewer
