// Geometry (see geometry_reader.h).
#include "common/collada/geometry_reader.h"

#include <cmath>
#include <cstring>
#include <string>

#include "common/collada/mesh_builder.h"
#include "common/collada/primitive_lists.h"
#include "common/collada/xml_values.h"

namespace pt::collada {

void GeometryReader::add(const XMLElement* inst, const Mat4& world) {
  const XMLElement* geom = doc_.resolve(inst, "url", "geometry");
  const std::vector<InstanceMaterial> bound = materials_.bindings(inst);
  if (const XMLElement* mesh = geom->FirstChildElement("mesh")) {
    add_mesh(geom, mesh, bound, world);
    return;
  }
  if (const XMLElement* t = cgl_technique(geom))
    if (const XMLElement* sphere = t->FirstChildElement("sphere")) {
      add_sphere(sphere, bound, world);
      return;
    }
  msg_.warn(geom, "has neither a <mesh> nor a CGL <sphere>; skipped");
}

void GeometryReader::add_sphere(const XMLElement* sphere, const std::vector<InstanceMaterial>& bound,
                                const Mat4& world) {
  msg_.check_children(sphere, {"radius"});
  const XMLElement* re = sphere->FirstChildElement("radius");
  if (!re) msg_.fail(sphere, "missing <radius>");
  const std::vector<double> v = numbers(msg_, re);
  if (v.size() != 1) msg_.fail(re, "expected 1 number, found " + std::to_string(v.size()));
  const double r = v[0];
  if (!std::isfinite(r) || r <= 0) msg_.fail(re, "the radius must be a positive finite number, not " + fmt(r));
  const Vec3d c = world.point({0, 0, 0});
  const double wr = r * norm(world.vector({1, 0, 0}));
  const Vec3 cf(c);
  const float rf = float(wr);
  if (!is_finite(cf) || !std::isfinite(rf) || !(rf > 0))
    msg_.fail(re, "the node transform makes the sphere degenerate (centre " + fmt(c) + ", radius " + fmt(wr) + ")");
  check_primitive_limit(msg_, sphere, scene_.num_primitives(), 1);
  Sphere s;
  s.center = cf;
  s.radius = rf;
  s.material = materials_.material_for(nullptr, bound);
  scene_.spheres.push_back(s);
}

void GeometryReader::add_mesh(const XMLElement* geom, const XMLElement* mesh,
                              const std::vector<InstanceMaterial>& bound, const Mat4& world) {
  const PrimitiveListContext ctx{msg_, doc_, sources_, scene_.num_primitives(),
                                 [&](const char* symbol) { return materials_.material_for(symbol, bound); }};
  MeshPrimitives prims;
  msg_.check_children(mesh, {"source", "vertices", "lines", "linestrips", "polygons", "polylist", "triangles",
                             "trifans", "tristrips", "extra"});
  for (const XMLElement* c = mesh->FirstChildElement(); c; c = c->NextSiblingElement()) {
    const char* name = c->Name();
    if (std::strcmp(name, "polylist") == 0 || std::strcmp(name, "triangles") == 0 ||
        std::strcmp(name, "polygons") == 0) {
      read_primitive_list(c, ctx, prims);
    } else if (std::strcmp(name, "lines") == 0 || std::strcmp(name, "linestrips") == 0 ||
               std::strcmp(name, "tristrips") == 0 || std::strcmp(name, "trifans") == 0) {
      msg_.warn(c, std::string("<") + name + "> primitives are not supported; skipped");
    }
  }
  MeshTriangles& tris = prims.triangles;
  if (tris.corners.empty()) return;

  const PositionData& pd = sources_.positions(prims.position_source);
  const std::vector<int> used = renumber_used_positions(tris.corners, pd.count());
  std::vector<Vec3> wp;
  if (const auto bad = world_positions(pd.xyz, used, world, &wp))
    msg_.fail(pd.array,
              "position " + std::to_string(bad->index) + " is not finite after the node transform " + fmt(bad->point));
  const size_t degenerate = add_mesh_triangles(wp, tris, scene_.triangles);
  if (degenerate > 0)
    msg_.warn(geom, "dropped " + std::to_string(degenerate) + " degenerate (zero-area) triangle" +
                        (degenerate == 1 ? "" : "s"));
}

}  // namespace pt::collada
