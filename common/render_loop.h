// The tiled parallel render loop: splits a rectangle of the image into
// 32x32 tiles, hands them to `threads` workers in order, shows a progress
// bar on stderr for renders that take more than a moment, and returns the
// sum of the workers' exact ray counters.
#pragma once
#include <functional>

#include "common/stats.h"

namespace pt {

// Pixels [x0, x1) x [y0, y1), (0, 0) at the bottom-left.
struct PixelRect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  long long area() const { return (long long)(x1 - x0) * (y1 - y0); }
};

struct RenderLoopOptions {
  int threads = 1;
  bool progress = true;   // draw a progress bar on stderr (only when it is a terminal)
  int tile_size = 32;
};

// Calls `pixel(x, y)` once for every pixel of `rect`, from `threads` threads.
// Each call must write only its own pixel's outputs. Exceptions thrown by
// `pixel` stop the render and are rethrown here.
RayStats render_tiles(const PixelRect& rect, const RenderLoopOptions& opts,
                      const std::function<void(int x, int y)>& pixel);

}  // namespace pt
