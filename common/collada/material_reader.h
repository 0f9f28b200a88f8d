// Materials: the <bind_material> of a geometry instance, the material a
// primitive list's symbol selects, and each <material> read once into the
// scene (a CGL material, else the profile_COMMON diffuse colour).
#pragma once
#include <string>
#include <unordered_map>
#include <vector>

#include "common/collada/document.h"
#include "common/collada/messages.h"
#include "common/scene.h"

namespace pt::collada {

// One <instance_material> of a <bind_material>.
struct InstanceMaterial {
  std::string symbol;
  const XMLElement* material;  // the <material> its target names
};

class MaterialReader {
 public:
  MaterialReader(Messages& msg, const Document& doc, std::vector<Material>& materials)
      : msg_(msg), doc_(doc), materials_(materials) {}

  // The materials an <instance_geometry> binds, in document order.
  std::vector<InstanceMaterial> bindings(const XMLElement* instance_geometry);

  // The scene material of a primitive list with material="symbol" (null
  // for none): the bound material with that symbol, else the first one,
  // else the default material. Each <material> is added once.
  int material_for(const char* symbol, const std::vector<InstanceMaterial>& bound);

 private:
  int default_material();
  Material read_material(const XMLElement* mat);
  void read_cgl_material(const XMLElement* type, Material& m);
  void read_common_diffuse(const XMLElement* effect, Material& m);

  Messages& msg_;
  const Document& doc_;
  std::vector<Material>& materials_;
  std::unordered_map<const XMLElement*, int> index_;  // <material> -> scene material
  int default_material_ = -1;
};

}  // namespace pt::collada
