#include "common/path_recorder.h"

namespace pt::detail {

void report_direct_begin(const Ray& r, const Hit& hit) { active_recorder->on_direct_begin(r, hit); }
void report_direct_end(const Color& L) { active_recorder->on_direct_end(L); }
void report_zero_bounce(const Color& L) { active_recorder->on_zero_bounce(L); }
void report_light_sample(const Light& light, const Vec3& p, float u1, float u2, const LightSample& s) {
  active_recorder->on_light_sample(light, p, u1, u2, s);
}

}  // namespace pt::detail
