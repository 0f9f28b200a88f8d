// Tests of materials: the CGL types, profile_COMMON diffuse colours,
// binding and its fallbacks, and colour checks.
#include <catch2/catch.hpp>

#include <string>
#include <utility>
#include <vector>

#include "tests/common/collada_documents.h"

using Catch::Matchers::Contains;
using namespace pt::test::dae;

TEST_CASE("CGL materials of every type and profile_COMMON diffuse", "[collada][materials]") {
  Doc d;
  d.effects = effect_cgl("e-emit", "<emission><radiance>10 20 30</radiance></emission>") +
              effect_cgl("e-mirror", "<mirror><reflectance>0.9 0.8 0.7</reflectance></mirror>") +
              effect_cgl("e-glass",
                         "<glass><reflectance>0.1 0.2 0.3</reflectance><transmittance>0.4 0.5 0.6"
                         "</transmittance><roughness>0.05</roughness><ior>1.45</ior></glass>") +
              effect_cgl("e-refr",
                         "<refraction><transmittance>0.7 0.8 0.9</transmittance><roughness>0.2</roughness>"
                         "<ior>1.33</ior></refraction>") +
              effect_cgl("e-micro", "<microfacet><alpha>0.3</alpha><eta>0.2 0.9 1.1</eta><k>3.9 2.4 2.2</k>"
                                    "</microfacet>") +
              effect_common("e-lambert", "lambert", "0.25 0.5 0.75 1") +
              effect_common("e-blinn", "blinn", "0.1 0.2 0.3");
  const std::vector<std::string> names = {"emit", "mirror", "glass", "refr", "micro", "lambert", "blinn"};
  std::string prims;
  std::vector<std::pair<std::string, std::string>> binding;
  for (const std::string& n : names) {
    d.materials += material(n, "e-" + n);
    prims += polylist("g", "3", "0 1 2", "s-" + n);
    binding.push_back({"s-" + n, n});
  }
  d.geometries = mesh("g", {0, 0, 0, 1, 0, 0, 0, 1, 0}, prims);
  d.nodes = node("", instance_geometry("g", binding));
  const Loaded l = load(d);
  REQUIRE(l.scene.triangles.size() == names.size());
  REQUIRE(l.scene.materials.size() == names.size());
  auto mat = [&](size_t i) -> const pt::Material& {
    const pt::Material& m = l.scene.materials.at(size_t(l.scene.triangles.at(i).material));
    CHECK(m.name == names[i]);
    return m;
  };
  const pt::Material& emit = mat(0);
  CHECK(emit.type == pt::MaterialType::Emission);
  check_vec(emit.emission, 10, 20, 30);
  check_vec(emit.albedo, 0, 0, 0);
  const pt::Material& mirror = mat(1);
  CHECK(mirror.type == pt::MaterialType::Mirror);
  check_vec(mirror.reflectance, 0.9, 0.8, 0.7);
  const pt::Material& glass = mat(2);
  CHECK(glass.type == pt::MaterialType::Glass);
  check_vec(glass.reflectance, 0.1, 0.2, 0.3);
  check_vec(glass.transmittance, 0.4, 0.5, 0.6);
  CHECK(glass.roughness == Approx(0.05));
  CHECK(glass.ior == Approx(1.45));
  const pt::Material& refr = mat(3);
  CHECK(refr.type == pt::MaterialType::Refraction);
  check_vec(refr.transmittance, 0.7, 0.8, 0.9);
  CHECK(refr.roughness == Approx(0.2));
  CHECK(refr.ior == Approx(1.33));
  const pt::Material& micro = mat(4);
  CHECK(micro.type == pt::MaterialType::Microfacet);
  CHECK(micro.alpha == Approx(0.3));
  check_vec(micro.eta, 0.2, 0.9, 1.1);
  check_vec(micro.k, 3.9, 2.4, 2.2);
  const pt::Material& lambert = mat(5);
  CHECK(lambert.type == pt::MaterialType::Diffuse);
  check_vec(lambert.albedo, 0.25, 0.5, 0.75);  // alpha ignored
  CHECK_FALSE(lambert.is_emissive());
  const pt::Material& blinn = mat(6);
  CHECK(blinn.type == pt::MaterialType::Diffuse);
  check_vec(blinn.albedo, 0.1, 0.2, 0.3);
}

TEST_CASE("material binding: fallbacks and de-duplication", "[collada][materials]") {
  Doc d = triangle_doc();
  d.effects = effect_common("fx-a", "phong", "0.1 0.1 0.1 1") + effect_common("fx-b", "phong", "0.2 0.2 0.2 1");
  d.materials = material("A", "fx-a") + material("B", "fx-b");
  d.geometries = mesh("tri", {0, 0, 0, 1, 0, 0, 0, 1, 0}, polylist("tri", "3", "0 1 2", "wanted"));
  SECTION("no bound material: the default diffuse 0.5") {
    d.nodes = node("", instance_geometry("tri"));
    const Loaded l = load(d);
    REQUIRE(l.scene.materials.size() == 1);
    const pt::Material& m = l.scene.materials[0];
    CHECK(m.name == "default");
    CHECK(m.type == pt::MaterialType::Diffuse);
    check_vec(m.albedo, 0.5, 0.5, 0.5);
    CHECK(l.scene.triangles.at(0).material == 0);
  }
  SECTION("an unmatched symbol takes the first instance_material") {
    d.nodes = node("", instance_geometry("tri", {{"other", "B"}, {"more", "A"}}));
    const Loaded l = load(d);
    CHECK(l.scene.materials.at(size_t(l.scene.triangles.at(0).material)).name == "B");
  }
  SECTION("one material per <material> used, shared between instances") {
    d.nodes = node("", instance_geometry("tri", {{"wanted", "A"}})) +
              node("<translate>0 0 1</translate>", instance_geometry("tri", {{"wanted", "A"}}));
    const Loaded l = load(d);
    REQUIRE(l.scene.triangles.size() == 2);
    CHECK(l.scene.materials.size() == 1);
    CHECK(l.scene.triangles[0].material == l.scene.triangles[1].material);
    CHECK(l.scene.materials[0].name == "A");
  }
}

TEST_CASE("material and light colours need the right number of numbers", "[collada][errors]") {
  Doc d = triangle_doc();
  d.materials = material("mat", "fx");
  d.nodes = node("", instance_geometry("tri", {{"s", "mat"}}));
  SECTION("profile_COMMON diffuse colour") {
    d.effects = effect_common("fx", "phong", "0.5 0.5");
    CHECK_THAT(error_of(d), Contains("<color>") && Contains("found 2"));
  }
  SECTION("CGL radiance") {
    d.effects = effect_cgl("fx", "<emission><radiance>1 1</radiance></emission>");
    CHECK_THAT(error_of(d), Contains("<radiance>") && Contains("found 2"));
  }
  SECTION("CGL eta") {
    d.effects = effect_cgl("fx", "<microfacet><alpha>0.5</alpha><eta>1 1 1 1</eta></microfacet>");
    CHECK_THAT(error_of(d), Contains("<eta>") && Contains("found 4"));
  }
  SECTION("negative colour") {
    d.effects = effect_common("fx", "lambert", "0.5 -0.5 0.5 1");
    CHECK_THAT(error_of(d), Contains("<color>") && Contains("negative"));
  }
  SECTION("light colour") {
    d.effects = effect_common("fx", "phong", "0.5 0.5 0.5");
    d.lights = light("L", "<point><color>1 1 1 1 1</color></point>");
    d.nodes += node("", instance_light("L"));
    CHECK_THAT(error_of(d), Contains("<color>") && Contains("found 5"));
  }
}
