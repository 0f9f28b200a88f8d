// The path inspector (viewer/debugger): a replayed sample's recorded steps
// add up bit for bit to what the render loop adds for that sample, on the
// code paths of parts 3, 4 and 5 (-o 0 and 1, Russian roulette on and off,
// light and hemisphere sampling), and what it lists (camera ray, light
// samples, shadow rays, Russian-roulette draws) is what was traced. All
// deterministic: fixed seeds, exact comparisons.
//
// Deliberate bug (planted in a scratch copy) -> tests here and in
// test_path_steps.cpp that failed on it:
//   weight not divided by the continue probability  -> adds up exactly (parts 4, 5)
//   a draw between events not counted (sync off)    -> Russian-roulette draws
//   zero bounce not recorded                        -> adds up exactly (every part)
//   shadow ray paired with the wrong light sample   -> several lights, several samples each
//   replaying the wrong sample (off by one)         -> camera ray; adds up exactly
//   an infinite max_t written as a bare inf         -> JSON of path records is valid
#include <catch2/catch.hpp>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <sstream>
#include <string>
#include <vector>

#include "common/collada.h"
#include "viewer/debugger/debugger.h"
#include "stages/part3_direct_lighting/direct_lighting.h"
#include "stages/part4_global_illumination/global_illumination.h"
#include "common/json.h"
#include "common/path_recorder.h"
#include "stages/part1_raytracing/pixel_sampling.h"
#include "pathtracer/render_job.h"
#include "tests/statistics/analytic_scenes.h"
#include "tests/debugger/json_read.h"
#include "tests/debugger/path_support.h"
#include "tests/support.h"
#include "common/todo.h"

using namespace pt;
using namespace pt::test;

using namespace pt::test::path;

namespace {

// A strict JSON reader that only says whether `text` is one valid JSON
// value (RFC 8259), so that the page can parse what the server sends.
class JsonCheck {
 public:
  explicit JsonCheck(const std::string& text) : s_(text) {}
  bool valid() {
    ws();
    if (!value()) return false;
    ws();
    return i_ == s_.size();
  }

 private:
  bool value() {
    if (i_ >= s_.size()) return false;
    const char c = s_[i_];
    if (c == '{') return object();
    if (c == '[') return array();
    if (c == '"') return string();
    if (c == '-' || (c >= '0' && c <= '9')) return number();
    return literal("true") || literal("false") || literal("null");
  }
  bool object() {
    ++i_;
    ws();
    if (eat('}')) return true;
    do {
      ws();
      if (!string()) return false;
      ws();
      if (!eat(':')) return false;
      ws();
      if (!value()) return false;
      ws();
    } while (eat(','));
    return eat('}');
  }
  bool array() {
    ++i_;
    ws();
    if (eat(']')) return true;
    do {
      ws();
      if (!value()) return false;
      ws();
    } while (eat(','));
    return eat(']');
  }
  bool string() {
    if (!eat('"')) return false;
    while (i_ < s_.size() && s_[i_] != '"') {
      if (static_cast<unsigned char>(s_[i_]) < 0x20) return false;
      if (s_[i_] == '\\') {
        ++i_;
        if (i_ >= s_.size() || std::string("\"\\/bfnrtu").find(s_[i_]) == std::string::npos) return false;
        if (s_[i_] == 'u') {
          for (int k = 0; k < 4; ++k)
            if (++i_ >= s_.size() || !std::isxdigit(static_cast<unsigned char>(s_[i_]))) return false;
        }
      }
      ++i_;
    }
    return eat('"');
  }
  bool number() {
    eat('-');
    if (eat('0')) {
    } else if (!digits()) {
      return false;
    }
    if (eat('.') && !digits()) return false;
    if (eat('e') || eat('E')) {
      if (!eat('+')) eat('-');
      if (!digits()) return false;
    }
    return true;
  }
  bool digits() {
    const size_t start = i_;
    while (i_ < s_.size() && s_[i_] >= '0' && s_[i_] <= '9') ++i_;
    return i_ > start;
  }
  bool literal(const char* word) {
    const std::string w(word);
    if (s_.compare(i_, w.size(), w) != 0) return false;
    i_ += w.size();
    return true;
  }
  bool eat(char c) {
    if (i_ < s_.size() && s_[i_] == c) {
      ++i_;
      return true;
    }
    return false;
  }
  void ws() {
    while (i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\n' || s_[i_] == '\t' || s_[i_] == '\r')) ++i_;
  }
  const std::string& s_;
  size_t i_ = 0;
};

// What the page reads from a record's JSON is the record: its figures bit
// for bit, every step, light sample and note.
void check_read_back(const debug::PathRecord& rec, const Json& j) {
  CHECK(j.num("part") == rec.part);
  REQUIRE(j.get("pixel") != nullptr);
  REQUIRE(j.get("pixel")->array.size() == 2);
  CHECK(j.get("pixel")->array[0].number == rec.x);
  CHECK(j.get("pixel")->array[1].number == rec.y);
  CHECK(j.num("sample") == rec.sample);
  CHECK(j.str("seed") == std::to_string(rec.seed));
  CHECK(j.num("samples_taken") == rec.samples_taken);
  CHECK(j.flag("camera_hit") == rec.camera_hit);
  CHECK(same_bits(read_vec(j.get("returned")), rec.returned));
  CHECK(same_bits(read_vec(j.get("sum_of_contributions")), rec.sum_of_contributions));
  CHECK(same_bits(read_vec(j.get("zero_bounce")), rec.zero_bounce));
  CHECK(j.flag("exact") == rec.exact);
  CHECK(j.flag("agrees") == rec.agrees);
  CHECK(j.str("end") == rec.end);
  CHECK(j.str("error") == rec.error);
  REQUIRE(j.get("camera_ray") != nullptr);
  CHECK(same_bits(read_vec(j.get("camera_ray")->get("direction")), rec.camera_ray.d));
  const Json* steps = j.get("steps");
  REQUIRE(steps != nullptr);
  REQUIRE(steps->array.size() == rec.steps.size());
  for (size_t k = 0; k < rec.steps.size(); ++k) {
    const Json& s = steps->array[k];
    const debug::PathStep& step = rec.steps[k];
    CHECK(s.num("bounce") == step.bounce);
    CHECK(s.str("material") == step.material);
    CHECK(same_bits(read_vec(s.get("point")), step.point));
    CHECK(same_bits(read_vec(s.get("path_weight")), step.path_weight));
    CHECK(same_bits(read_vec(s.get("radiance_added")), step.radiance_added));
    const Json* ls = s.get("light_samples");
    const Json* hs = s.get("hemisphere_samples");
    CHECK((ls ? ls->array.size() : 0) == step.light_samples.size());
    CHECK((hs ? hs->array.size() : 0) == step.hemisphere_samples.size());
    for (size_t i = 0; ls && i < std::min(ls->array.size(), step.light_samples.size()); ++i) {
      CHECK(ls->array[i].str("verdict") == step.light_samples[i].verdict);
      CHECK(same_bits(read_vec(ls->array[i].get("contribution")), step.light_samples[i].contribution));
    }
  }
  const Json* notes = j.get("notes");
  REQUIRE(notes != nullptr);
  REQUIRE(notes->array.size() == rec.notes.size());
  for (size_t i = 0; i < rec.notes.size(); ++i) CHECK(notes->array[i].string == rec.notes[i]);
  REQUIRE(j.get("todos") != nullptr);
  CHECK(j.get("todos")->array.size() == rec.todos.size());
}
}  // namespace

TEST_CASE("JSON of path records is valid, for every kind of record", "[debugger]") {
  CHECK(JsonCheck("{\"a\": [1, -2.5e-3, \"x\\n\", true, null, {}]}").valid());
  CHECK_FALSE(JsonCheck("{\"a\": nan}").valid());
  CHECK_FALSE(JsonCheck("{\"a\": [1, 2,]}").valid());
  CHECK_FALSE(JsonCheck("{\"a\": 1} x").valid());
  const int w = 12, h = 9;
  const Scene scene = small_scene("CBlights.dae", w, h);
  int records = 0;
  for (int part = 1; part <= 5; ++part)
    for (bool hemisphere : {false, true}) {
      RenderOptions o = options(part, w, h, 2, 5, 81);
      o.hemisphere_sampling = hemisphere;
      const auto geometry = debug::make_geometry(scene, o);
      for (int y = 0; y < h; y += 2)
        for (int x = 0; x < w; x += 2) {
          const debug::PathRecord rec = debug::record_path(scene, *geometry, o, x, y, 1);
          const std::string json = rec.to_json();
          INFO("part " << part << " pixel (" << x << ", " << y << "): " << json);
          CHECK(JsonCheck(json).valid());
          check_read_back(rec, parse_json(json, "a path record"));
          ++records;
        }
    }
  CHECK(records == 5 * 2 * 30);
  // Records with an error and with TODO lines.
  const RenderOptions o = options(4, w, h, 1, 3, 71);
  const ThrowingGeometry throwing;
  const debug::PathRecord failed = debug::record_path(scene, throwing, o, 2, 2, 0);
  CHECK(JsonCheck(failed.to_json()).valid());
  check_read_back(failed, parse_json(failed.to_json(), "a failed path record"));
}

TEST_CASE("part 3: the recorded steps add up exactly to the render loop's sample, light and hemisphere sampling",
          "[debugger][part3]") {
  const int w = 16, h = 12;
  const Scene scene = small_scene("CBlights.dae", w, h);
  RenderOptions o = options(3, w, h, 2, 1, 7);
  o.light_samples = 2;
  const Coverage light = check_adds_up(scene, o, "part 3, light sampling");
  CHECK(light.blocked > 0);  // the spheres shadow the floor
  CHECK(light.lit > 0);
  CHECK(light.probes == 0);
  o.hemisphere_sampling = true;
  const Coverage hemi = check_adds_up(scene, o, "part 3, -H");
  CHECK(hemi.probes > 0);
  CHECK(hemi.lit + hemi.blocked == 0);
}

TEST_CASE("part 4: the recorded steps add up exactly, -o 0 and 1, Russian roulette on and off, -H",
          "[debugger][part4]") {
  const int w = 12, h = 9;
  const Scene scene = small_scene("CBlights.dae", w, h);
  for (bool accumulate : {true, false})
    for (bool rr : {true, false}) {
      RenderOptions o = options(4, w, h, 3, 6, 11);
      o.accumulate_bounces = accumulate;
      o.russian_roulette = rr;
      const std::string what = std::string("part 4 -m 6 -o ") + (accumulate ? "1" : "0") + (rr ? "" : " --no-rr");
      const Coverage c = check_adds_up(scene, o, what);
      INFO(what);
      CHECK(c.longest >= 4);
      if (rr)
        CHECK(c.roulette_deaths > 0);
      else
        CHECK(c.roulette_deaths == 0);
    }
  RenderOptions o = options(4, w, h, 2, 4, 12);
  o.hemisphere_sampling = true;
  CHECK(check_adds_up(scene, o, "part 4 -m 4 -H").probes > 0);
  o = options(4, w, h, 2, 4, 13);
  o.indirect_only = true;
  check_adds_up(scene, o, "part 4 -m 4 --indirect-only");
  o = options(4, w, h, 2, 0, 14);
  check_adds_up(scene, o, "part 4 -m 0");
}

TEST_CASE("part 4 under the sky: rays that escape add exactly what the render loop adds", "[debugger][part4]") {
  const int w = 12, h = 9;
  const Scene scene = small_scene("sphere_ambient.dae", w, h);
  RenderOptions o = options(4, w, h, 2, 5, 21);
  const Coverage c = check_adds_up(scene, o, "sphere_ambient -m 5");
  CHECK(c.escaped > 0);
  o.part = 3;
  o.hemisphere_sampling = true;
  check_adds_up(scene, o, "sphere_ambient part 3 -H");
}

TEST_CASE("part 5: the replay follows adaptive sampling and adds up exactly", "[debugger][part5]") {
  const int w = 10, h = 8;
  const Scene scene = small_scene("CBlights.dae", w, h);
  for (bool hemisphere : {false, true}) {
    RenderOptions o = options(5, w, h, 12, 5, 31);
    o.adaptive_batch = 4;
    o.adaptive_tolerance = 0.3;
    o.hemisphere_sampling = hemisphere;
    o.accumulate_bounces = !hemisphere;
    check_adds_up(scene, o, hemisphere ? "part 5 -H -o 0" : "part 5");
  }
}

TEST_CASE("parts 1 and 2: the record is the normal-shaded camera ray", "[debugger][part1][part2]") {
  const int w = 8, h = 6;
  const Scene scene = small_scene("CBspheres_lambertian.dae", w, h);
  for (int part : {1, 2}) {
    const RenderOptions o = options(part, w, h, 2, 1, 3);
    check_adds_up(scene, o, "part " + std::to_string(part));
    const auto geometry = debug::make_geometry(scene, o);
    const debug::PathRecord rec = debug::record_path(scene, *geometry, o, w / 2, h / 2, 1);
    REQUIRE(rec.steps.size() == 1);
    CHECK(same_bits(rec.returned, rec.steps[0].hit.n * 0.5f + Color(0.5f)));
  }
}

TEST_CASE("the recorded camera ray is the render loop's ray for that sample", "[debugger]") {
  const int w = 16, h = 12;
  const Scene scene = small_scene("CBlights.dae", w, h);
  const RenderOptions o = options(4, w, h, 5, 3, 99);
  const auto geometry = debug::make_geometry(scene, o);
  for (int s = 0; s < o.samples_per_pixel; ++s) {
    const int x = 3 + s, y = 7;
    Rng rng = Rng::for_sample(o.seed, uint64_t(y) * w + x, uint64_t(s));
    const Ray expected = camera_sample_ray(scene.camera, x, y, true, rng);
    const debug::PathRecord rec = debug::record_path(scene, *geometry, o, x, y, s);
    INFO("sample " << s);
    CHECK(same_bits(rec.camera_ray.o, expected.o));
    CHECK(same_bits(rec.camera_ray.d, expected.d, rec.camera_ray.max_t, expected.max_t));
  }
}
