// Materials (see material_reader.h).
#include "common/collada/material_reader.h"

#include <cstring>
#include <limits>
#include <string_view>

#include "common/collada/xml_values.h"

namespace pt::collada {

std::vector<InstanceMaterial> MaterialReader::bindings(const XMLElement* inst) {
  std::vector<InstanceMaterial> bound;
  msg_.check_children(inst, {"bind_material", "extra"});
  if (const XMLElement* bm = inst->FirstChildElement("bind_material")) {
    msg_.check_children(bm, {"param", "technique_common", "technique", "extra"});
    if (const XMLElement* tc = bm->FirstChildElement("technique_common")) {
      msg_.check_children(tc, {"instance_material"});
      for (const XMLElement* im = tc->FirstChildElement("instance_material"); im;
           im = im->NextSiblingElement("instance_material")) {
        const char* symbol = im->Attribute("symbol");
        bound.push_back({symbol ? symbol : "", doc_.resolve(im, "target", "material")});
      }
    }
  }
  return bound;
}

int MaterialReader::default_material() {
  if (default_material_ < 0) {
    Material m;
    m.name = "default";
    m.type = MaterialType::Diffuse;
    m.albedo = Color(0.5f);
    default_material_ = int(materials_.size());
    materials_.push_back(m);
  }
  return default_material_;
}

int MaterialReader::material_for(const char* symbol, const std::vector<InstanceMaterial>& bound) {
  if (bound.empty()) return default_material();
  const InstanceMaterial* chosen = &bound.front();
  if (symbol)
    for (const InstanceMaterial& b : bound)
      if (b.symbol == symbol) {
        chosen = &b;
        break;
      }
  const auto it = index_.find(chosen->material);
  if (it != index_.end()) return it->second;
  Material m = read_material(chosen->material);
  const int i = int(materials_.size());
  materials_.push_back(std::move(m));
  index_.emplace(chosen->material, i);
  return i;
}

Material MaterialReader::read_material(const XMLElement* mat) {
  Material m;
  m.name = mat->Attribute("id") ? mat->Attribute("id") : "";
  const XMLElement* ie = mat->FirstChildElement("instance_effect");
  if (!ie) msg_.fail(mat, "missing <instance_effect>");
  const XMLElement* effect = doc_.resolve(ie, "url", "effect");

  if (const XMLElement* t = cgl_technique(effect)) {
    const XMLElement* type = t->FirstChildElement();
    static const char* const known[] = {"emission", "mirror", "glass", "refraction", "microfacet"};
    for (const char* k : known)
      if (std::strcmp(type->Name(), k) == 0) {
        read_cgl_material(type, m);
        return m;
      }
    msg_.warn(type, "unknown CGL material type; using the effect's diffuse colour");
  }
  read_common_diffuse(effect, m);
  return m;
}

// profile_COMMON: the diffuse colour of the first shading model.
void MaterialReader::read_common_diffuse(const XMLElement* effect, Material& m) {
  const XMLElement* prof = effect->FirstChildElement("profile_COMMON");
  const XMLElement* tech = prof ? prof->FirstChildElement("technique") : nullptr;
  if (!tech) return;
  msg_.check_children(tech, {"asset", "image", "newparam", "constant", "lambert", "phong", "blinn", "extra"});
  for (const XMLElement* model = tech->FirstChildElement(); model; model = model->NextSiblingElement()) {
    const char* name = model->Name();
    if (std::strcmp(name, "phong") && std::strcmp(name, "lambert") && std::strcmp(name, "blinn") &&
        std::strcmp(name, "constant"))
      continue;
    msg_.check_children(model, {"emission", "ambient", "diffuse", "specular", "shininess", "reflective",
                                "reflectivity", "transparent", "transparency", "index_of_refraction"});
    if (const XMLElement* diffuse = model->FirstChildElement("diffuse")) {
      if (const XMLElement* c = diffuse->FirstChildElement("color"))
        m.albedo = Color(rgb(msg_, c, true));
      else
        msg_.warn(diffuse, "only a <color> is supported (textures are not); using diffuse 0.5");
    }
    break;
  }
}

// A CGL material type the loader knows (emission, mirror, glass,
// refraction, microfacet) and its parameters.
void MaterialReader::read_cgl_material(const XMLElement* type, Material& m) {
  auto color = [&](const char* name, Color& out) {
    if (const XMLElement* e = type->FirstChildElement(name)) out = Color(rgb(msg_, e, false));
  };
  auto number = [&](const char* name, float& out, double lo, bool lo_inclusive) {
    if (const XMLElement* e = type->FirstChildElement(name)) {
      const double v = scalar(msg_, e, name);
      if (lo_inclusive ? v < lo : v <= lo)
        msg_.fail(e, std::string("must be ") + (lo_inclusive ? ">= " : "> ") + fmt(lo) + ", found " + fmt(v));
      if (v > std::numeric_limits<float>::max()) msg_.fail(e, fmt(v) + " is too large for single precision");
      out = float(v);
    }
  };
  const std::string_view t = type->Name();
  if (t == "emission") {
    msg_.check_children(type, {"radiance"});
    m.type = MaterialType::Emission;
    m.albedo = Color(0.0f);
    color("radiance", m.emission);
  } else if (t == "mirror") {
    msg_.check_children(type, {"reflectance"});
    m.type = MaterialType::Mirror;
    color("reflectance", m.reflectance);
  } else if (t == "glass") {
    msg_.check_children(type, {"reflectance", "transmittance", "roughness", "ior"});
    m.type = MaterialType::Glass;
    color("reflectance", m.reflectance);
    color("transmittance", m.transmittance);
    number("roughness", m.roughness, 0.0, true);
    number("ior", m.ior, 0.0, false);
  } else if (t == "refraction") {
    msg_.check_children(type, {"transmittance", "roughness", "ior"});
    m.type = MaterialType::Refraction;
    color("transmittance", m.transmittance);
    number("roughness", m.roughness, 0.0, true);
    number("ior", m.ior, 0.0, false);
  } else if (t == "microfacet") {
    msg_.check_children(type, {"alpha", "eta", "k"});
    m.type = MaterialType::Microfacet;
    number("alpha", m.alpha, 0.0, false);
    color("eta", m.eta);
    color("k", m.k);
  }
}

}  // namespace pt::collada
