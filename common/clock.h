// Wall-clock time for the figures the renderer and the grader report.
#pragma once
#include <chrono>

namespace pt {

using Clock = std::chrono::steady_clock;

// Seconds from `t0` to now.
inline double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

}  // namespace pt
