// How Catch prints the project's vectors and colours in a failed assertion:
// "(0.3, -0.2, 0.93)" instead of "{?}", so that `REQUIRE(wi == Vec3(...))`
// shows both sides. tests/CMakeLists.txt includes it in every test source
// (-include), before anything else.
#pragma once
#include <catch2/catch.hpp>
#include <sstream>
#include <string>

#include "common/vec3.h"

namespace Catch {
template <typename T>
struct StringMaker<pt::Vec3T<T>> {
  static std::string convert(const pt::Vec3T<T>& v) {
    std::ostringstream s;
    s.precision(8);
    s << "(" << v.x << ", " << v.y << ", " << v.z << ")";
    return s.str();
  }
};
}  // namespace Catch
