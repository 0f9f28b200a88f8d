#include "common/stats.h"

namespace pt {

RayStats& thread_ray_stats() {
  static thread_local RayStats stats;
  return stats;
}

}  // namespace pt
