#include "common/path_recorder.h"

namespace pt::detail {

void report_direct_begin(const Ray& r, const Hit& hit) { active_recorder->on_direct_begin(r, hit); }
void report_direct_end(const Color& L) { active_recorder->on_direct_end(L); }
void report_zero_bounce(const Color& L) { active_recorder->on_zero_bounce(L); }

}  // namespace pt::detail
