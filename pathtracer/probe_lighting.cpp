// The function checks of part 3's light estimators and part 4's path
// (probe.h): they need a scene.
#include "pathtracer/probe.h"

namespace pt::probe {

std::vector<FunctionProbe> probes_lighting() { return {}; }

}  // namespace pt::probe
