// Lights (see light_reader.h).
#include "common/collada/light_reader.h"

#include <limits>
#include <string>
#include <string_view>

#include "common/collada/xml_values.h"

namespace pt::collada {

namespace {

// The element naming the light's type (<area>, <point>, ...), or null with
// a warning when the light is skipped.
const XMLElement* light_type(Messages& msg, const XMLElement* light) {
  const XMLElement* tech = cgl_technique(light);
  if (!tech) tech = light->FirstChildElement("technique_common");
  const XMLElement* type = tech ? tech->FirstChildElement() : nullptr;
  if (!type) {
    msg.warn(light, "has no light type under <technique_common> or a CGL technique; skipped");
    return nullptr;
  }
  const std::string_view t = type->Name();
  if (t == "spot") {
    msg.warn(light, "spot lights are not supported; skipped");
    return nullptr;
  }
  if (t != "area" && t != "point" && t != "directional" && t != "ambient") {
    msg.warn(light, "unknown light type <" + std::string(t) + ">; skipped");
    return nullptr;
  }
  return type;
}

// An area light: the unit square of the node's x-y plane, facing -z.
void place_area(const Messages& msg, const XMLElement* inst, const Mat4& world, Light& l) {
  const Vec3d c = world.point({0, 0, 0});
  l.type = LightType::Area;
  const Vec3d dx = world.point({-1, 0, 0}) - c, dy = world.point({0, 1, 0}) - c;
  const Vec3d d = world.point({0, 0, -1}) - c;
  if (norm2(cross(dx, dy)) == 0 || norm2(d) == 0)
    msg.fail(inst, "the node transform makes the area light degenerate (zero area or no direction)");
  l.position = Vec3(c);
  l.dim_x = Vec3(dx);
  l.dim_y = Vec3(dy);
  l.direction = Vec3(normalize(d));
}

// A point light at the node's origin with COLLADA's attenuation.
void place_point(const Messages& msg, const XMLElement* type, const Mat4& world, Light& l) {
  l.type = LightType::Point;
  l.position = Vec3(world.point({0, 0, 0}));
  auto atten = [&](const char* name, float& out) {
    if (const XMLElement* e = type->FirstChildElement(name)) {
      const double v = scalar(msg, e, name);
      if (v < 0) msg.fail(e, "attenuation must not be negative, found " + fmt(v));
      if (v > std::numeric_limits<float>::max()) msg.fail(e, fmt(v) + " is too large for single precision");
      out = float(v);
    }
  };
  atten("constant_attenuation", l.constant_attenuation);
  atten("linear_attenuation", l.linear_attenuation);
  atten("quadratic_attenuation", l.quadratic_attenuation);
  if (l.constant_attenuation == 0 && l.linear_attenuation == 0 && l.quadratic_attenuation == 0)
    msg.fail(type, "all attenuation coefficients are zero (the intensity would be infinite)");
}

}  // namespace

std::optional<Light> read_light(Messages& msg, const Document& doc, const XMLElement* inst, const Mat4& world) {
  const XMLElement* light = doc.resolve(inst, "url", "light");
  const XMLElement* type = light_type(msg, light);
  if (!type) return std::nullopt;
  const std::string_view t = type->Name();
  if (t == "point")
    msg.check_children(type, {"color", "constant_attenuation", "linear_attenuation", "quadratic_attenuation"});
  else
    msg.check_children(type, {"color"});
  const XMLElement* ce = type->FirstChildElement("color");
  if (!ce) msg.fail(type, "missing <color>");
  Light l;
  l.radiance = Color(rgb(msg, ce, false));

  if (t == "area") {
    place_area(msg, inst, world, l);
  } else if (t == "point") {
    place_point(msg, type, world, l);
  } else if (t == "directional") {
    l.type = LightType::Directional;
    const Vec3d d = world.vector({0, 0, -1});  // rotation (linear part) only
    if (norm2(d) == 0) msg.fail(inst, "the node transform gives the directional light no direction");
    l.direction = Vec3(normalize(d));
  } else {
    l.type = LightType::Ambient;
  }
  if (!is_finite(l.position) || !is_finite(l.direction) || !is_finite(l.dim_x) || !is_finite(l.dim_y))
    msg.fail(inst, "the node transform puts the light at a non-finite place");
  return l;
}

}  // namespace pt::collada
