// Debug mode's sampling tools as the page calls them (viewer/debug_api.h):
// "bsdf" (the BSDF sampler at a pixel's first hit) and "envmap" (where the
// -e map is sampled): the JSON the page reads, and refusals.
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "common/collada.h"
#include "common/environment.h"
#include "common/json.h"
#include "pathtracer/env_probability.h"
#include "pathtracer/render_job.h"
#include "viewer/debug_api.h"
#include "viewer/debugger/debugger.h"

using namespace pt;

namespace {

const std::string kScenes = PT_PROJECT_SCENES_DIR;

// The viewer's settings -r 400 300 --part `part` on a project scene (the
// course's view, a centre crop), with -e `env` when given.
RenderOptions settings(const std::string& scene, int part, const std::string& env = "") {
  RenderOptions o;
  o.part = part;
  o.width = 400;
  o.height = 300;
  o.scene_path = kScenes + "/" + scene;
  if (!env.empty()) o.env_map = kScenes + "/" + env;
  return o;
}

Scene load(const RenderOptions& o) {
  Scene s = load_collada(o.scene_path);
  if (!o.env_map.empty()) {
    Light env;
    env.type = LightType::Environment;
    env.environment = std::make_shared<const EnvironmentMap>(load_environment_map(o.env_map));
    s.lights.push_back(env);
  }
  configure_camera(s.camera, o);
  return s;
}

Json call(const std::string& tool, const std::string& input, const RenderOptions& o) {
  return parse_json(viewer::run_debug_tool(tool, input, o, [&] { return load(o); }), tool);
}

std::string base64_decode(const std::string& text) {
  const std::string digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  unsigned bits = 0;
  int have = 0;
  for (char c : text) {
    if (c == '=') break;
    bits = bits << 6 | unsigned(digits.find(c));
    have += 6;
    if (have >= 8) {
      have -= 8;
      out += char(bits >> have & 0xff);
    }
  }
  return out;
}

}  // namespace

TEST_CASE("Debug mode's BSDF sampler: a glass pixel's two directions, a metal pixel's histogram", "[viewer]") {
  // CBspheres at part 6: pixel (300, 50) of the 400 x 300 crop is the glass sphere.
  const RenderOptions o6 = settings("CBspheres.dae", 6);
  const Json glass = call("bsdf", R"({"x":300,"y":50,"samples":4096,"seed":1})", o6);
  CHECK(glass.str("material_name") == "glass-material (glass)");
  CHECK(glass.str("model") == "glass");
  CHECK(glass.flag("delta"));
  CHECK(glass.get("histogram") == nullptr);
  const Json* dirs = glass.get("directions");
  REQUIRE(dirs);
  REQUIRE(dirs->array.size() == 2);
  int counted = 0;
  double probability = 0;
  for (const Json& d : dirs->array) {
    counted += int(d.num("count"));
    probability += d.num("pdf");
    CHECK((d.str("scatter") == "reflected" || d.str("scatter") == "refracted"));
    CHECK(std::fabs(d.num("z")) <= debug::kBsdfZBound);
  }
  CHECK(counted == 4096);
  CHECK(std::fabs(probability - 1) <= 1e-6);  // R + (1 - R)
  CHECK(glass.get("samples")->array.size() == 4096);
  CHECK(glass.flag("agrees"));
  CHECK(glass.num("part") == 6);
  CHECK(glass.get("pixel")->array.at(0).number == 300);
  CHECK(glass.get("wo_local")->array.at(2).number > 0);  // the camera is outside the sphere

  // At part 5 the glass is the stand-in that reflects nothing: no direction.
  const Json black = call("bsdf", R"({"x":300,"y":50,"samples":16,"seed":1})", settings("CBspheres.dae", 5));
  CHECK(black.str("model") == "not rendered");
  CHECK(black.num("no_direction") == 16);

  // CBspheres_microfacet at part 7: (300, 50) the gold sphere (alpha 0.25),
  // (100, 50) the copper one (alpha 0.05).
  const RenderOptions o7 = settings("CBspheres_microfacet.dae", 7);
  for (const char* input :
       {R"({"x":300,"y":50,"samples":4096,"seed":1})", R"({"x":100,"y":50,"samples":4096,"seed":2})"}) {
    const Json metal = call("bsdf", input, o7);
    INFO(input << ": " << metal.str("verdict"));
    CHECK(metal.str("model") == "microfacet");
    CHECK_FALSE(metal.flag("delta"));
    const Json* bins = metal.get("histogram");
    REQUIRE(bins);
    CHECK(bins->array.size() == 30);
    int total = int(metal.num("no_direction"));
    for (const Json& b : bins->array) {
      total += int(b.num("count"));
      REQUIRE(b.get("theta")->array.size() == 2);
      CHECK(b.get("sampled_density") != nullptr);
      CHECK(b.get("pdf_density") != nullptr);
    }
    CHECK(total == 4096);
    CHECK(metal.flag("agrees"));
    CHECK(metal.num("pdf_integral") > 0.5);
    CHECK(metal.num("z_bound") == debug::kBsdfZBound);
  }
}

TEST_CASE("Debug mode's BSDF sampler refuses pixels off the image, off the scene, and bad counts", "[viewer]") {
  const RenderOptions o = settings("CBspheres.dae", 6);
  int loads = 0;
  const auto counted_load = [&] {
    ++loads;
    return load(o);
  };
  using debug::InputError;
  CHECK_THROWS_AS(viewer::run_debug_tool("bsdf", R"({"x":400,"y":0,"samples":8,"seed":1})", o, counted_load),
                  InputError);
  CHECK_THROWS_AS(viewer::run_debug_tool("bsdf", R"({"x":0,"y":-1,"samples":8,"seed":1})", o, counted_load),
                  InputError);
  CHECK_THROWS_AS(viewer::run_debug_tool("bsdf", R"({"x":1,"y":1,"samples":0,"seed":1})", o, counted_load), InputError);
  CHECK_THROWS_AS(viewer::run_debug_tool("bsdf", R"({"x":1,"y":1,"samples":65537,"seed":1})", o, counted_load),
                  InputError);
  CHECK_THROWS_AS(viewer::run_debug_tool("bsdf", R"({"x":1,"y":1,"seed":1})", o, counted_load), InputError);
  CHECK(loads == 0);  // refused before the scene is read
  // A pixel whose ray leaves the scene (the sky above the bunny's plane).
  RenderOptions open = settings("bunny_microfacet_envmap.dae", 8);
  try {
    viewer::run_debug_tool("bsdf", R"({"x":0,"y":299,"samples":8,"seed":1})", open, [&] { return load(open); });
    FAIL("a pixel of the sky was sampled");
  } catch (const InputError& e) {
    CHECK(std::string(e.what()).find("hits nothing") != std::string::npos);
  }
}

TEST_CASE("Debug mode's environment density is pathtracer --env-probability's picture, with its figures", "[viewer]") {
  const RenderOptions o8 = settings("bunny_microfacet_envmap.dae", 8, "sky_sun.exr");
  const Json d8 = call("envmap", "{}", o8);
  const EnvironmentMap map = load_environment_map(o8.env_map);
  CHECK(d8.num("width") == map.width);
  CHECK(d8.num("height") == map.height);
  CHECK(d8.str("sampler") == "importance (part 8)");
  CHECK(std::fabs(d8.num("total") - 1) <= 1e-6);
  CHECK(d8.num("max_ratio") > 100);    // the sun: far likelier than the average texel
  CHECK(d8.num("top_share") > 0.5);    // most directions go to 1% of the map
  const std::string url = d8.str("png");
  const std::string prefix = "data:image/png;base64,";
  REQUIRE(url.rfind(prefix, 0) == 0);
  std::string note;
  const std::vector<uint8_t> want = encode_environment_probability_png(map, 8, &note);
  CHECK(base64_decode(url.substr(prefix.size())) == std::string(want.begin(), want.end()));

  // Before part 8: uniform over the sphere, no texel much likelier than another.
  const Json d7 = call("envmap", "{}", settings("bunny_microfacet_envmap.dae", 7, "sky_sun.exr"));
  CHECK(d7.str("sampler") == "uniform over the sphere");
  CHECK(d7.num("max_ratio") < 1.6);  // the equator's texels: pi / 2 times the average
  CHECK(d7.num("top_share") < 0.02);

  // No map, or parts 1-2: refused with the reason.
  using debug::InputError;
  CHECK_THROWS_AS(call("envmap", "{}", settings("bunny_microfacet_envmap.dae", 8)), InputError);
  CHECK_THROWS_AS(call("envmap", "{}", settings("bunny_microfacet_envmap.dae", 2, "sky_sun.exr")), InputError);
}
