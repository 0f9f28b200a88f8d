// The path inspector (viewer/debugger): a replayed sample's recorded steps
// add up bit for bit to what the render loop adds for that sample, on the
// code paths of parts 3, 4 and 5 (-o 0 and 1, Russian roulette on and off,
// light and hemisphere sampling), and what it lists (camera ray, light
// samples, shadow rays, Russian-roulette draws) is what was traced. All
// deterministic: fixed seeds, exact comparisons.
//
// Deliberate bug (planted in a scratch copy) -> tests here that failed on it:
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
#include "tests/support.h"
#include "common/todo.h"

using namespace pt;
using namespace pt::test;

namespace {

bool same_bits(const Color& a, const Color& b) {
  const float x[3] = {a.x, a.y, a.z}, y[3] = {b.x, b.y, b.z};
  return std::memcmp(x, y, sizeof x) == 0;
}

bool same_bits(const Vec3& a, const Vec3& b, float s, float t) {
  return same_bits(a, b) && std::memcmp(&s, &t, sizeof s) == 0;
}

std::string show(const Color& c) {
  std::ostringstream o;
  o.precision(9);
  o << "(" << c.x << ", " << c.y << ", " << c.z << ")";
  return o.str();
}

RenderOptions options(int part, int w, int h, int spp, int max_depth, uint64_t seed) {
  RenderOptions o;
  o.part = part;
  o.width = w;
  o.height = h;
  o.samples_per_pixel = spp;
  o.max_depth = max_depth;
  o.seed = seed;
  o.threads = 1;
  o.progress = false;
  return o;
}

Scene small_scene(const std::string& name, int w, int h) {
  Scene s = load_collada(project_scene(name));
  fit_course_view(s.camera, w, h);
  return s;
}

// What the replays of one configuration showed, to check that the test saw
// the features it claims to cover.
struct Coverage {
  int records = 0, exact = 0, pixels = 0, pixels_equal = 0;
  int longest = 0;               // most steps in one path
  int roulette_deaths = 0;       // paths ended by a draw >= 0.7
  int blocked = 0, lit = 0;      // light samples
  int probes = 0;                // hemisphere samples
  int escaped = 0;               // camera rays that hit nothing
};

// Renders the whole image with the command line's render_scene, replays
// every sample of every pixel and checks (1) each record adds up exactly,
// (2) the average of the replayed samples is exactly the rendered pixel
// and (3) part 5's sample counts agree.
Coverage check_adds_up(const Scene& scene, const RenderOptions& o, const std::string& what) {
  Coverage c;
  const RenderResult render = render_scene(scene, o);
  const auto geometry = debug::make_geometry(scene, o);
  for (int y = 0; y < o.height; ++y)
    for (int x = 0; x < o.width; ++x) {
      const int taken = int(render.image.samples[render.image.index(x, y)]);
      Color sum(0.0f);
      for (int s = 0; s < taken; ++s) {
        const debug::PathRecord rec = debug::record_path(scene, *geometry, o, x, y, s);
        ++c.records;
        INFO(what << ", pixel (" << x << ", " << y << ") sample " << s << ": " << rec.error << " returned "
                  << show(rec.returned) << ", steps add up to " << show(rec.sum_of_contributions));
        REQUIRE(rec.ok());
        CHECK(rec.samples_taken == taken);
        c.exact += rec.exact ? 1 : 0;
        CHECK(rec.exact);
        sum += rec.returned;
        c.longest = std::max(c.longest, int(rec.steps.size()));
        c.escaped += rec.camera_hit ? 0 : 1;
        if (rec.end.rfind("Russian roulette", 0) == 0) ++c.roulette_deaths;
        for (const debug::PathStep& st : rec.steps) {
          c.probes += int(st.hemisphere_samples.size());
          for (const debug::LightSampleStep& l : st.light_samples) {
            c.blocked += l.verdict == "blocked" ? 1 : 0;
            c.lit += l.verdict == "lit" ? 1 : 0;
          }
        }
      }
      ++c.pixels;
      const Color replayed = sum / float(taken);
      INFO(what << ", pixel (" << x << ", " << y << "): rendered " << show(render.image.at(x, y)) << ", replayed "
                << show(replayed));
      c.pixels_equal += same_bits(replayed, render.image.at(x, y)) ? 1 : 0;
      CHECK(same_bits(replayed, render.image.at(x, y)));
    }
  CHECK(c.exact == c.records);
  CHECK(c.pixels_equal == c.pixels);
  return c;
}

// Geometry standing in for a student's that throws.
class ThrowingGeometry final : public Intersector {
 public:
  bool intersect(Ray&, Hit*) const override { throw std::runtime_error("node index out of range"); }
  bool occluded(const Ray&) const override { return false; }
};

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

TEST_CASE("light samples of a point light: each has its shadow ray and the lit ones add up to the direct estimate",
          "[debugger][part3]") {
  // CBempty: one point light (a delta light takes one sample), so the
  // estimate at a hit is exactly the one sample's f L cos / pdf when lit.
  const int w = 16, h = 12;
  const Scene scene = small_scene("CBempty.dae", w, h);
  const RenderOptions o = options(3, w, h, 1, 1, 5);
  const auto geometry = debug::make_geometry(scene, o);
  int lit = 0, steps = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const debug::PathRecord rec = debug::record_path(scene, *geometry, o, x, y, 0);
      REQUIRE(rec.ok());
      if (rec.steps.empty()) continue;
      const debug::PathStep& st = rec.steps[0];
      ++steps;
      INFO("pixel (" << x << ", " << y << ") " << rec.to_json());
      REQUIRE(st.direct_estimated);
      REQUIRE(st.light_samples.size() == 1);
      const debug::LightSampleStep& l = st.light_samples[0];
      CHECK(l.light == 0);
      CHECK(l.sample.pdf == 1.0f);
      if (l.verdict == "lit" || l.verdict == "blocked") {
        CHECK(l.shadow_traced);
        CHECK(same_bits(l.shadow_ray.o, st.point));
        CHECK(same_bits(l.shadow_ray.d, l.sample.wi));
        CHECK(l.shadow_ray.min_t == kRayEpsilon);
        CHECK(l.shadow_ray.max_t == l.sample.distance - kRayEpsilon);
        CHECK(l.blocked == (l.verdict == "blocked"));
      } else {
        CHECK(!l.shadow_traced);
      }
      if (l.verdict == "lit") ++lit;
      CHECK(same_bits(st.direct, l.contribution));
    }
  CHECK(steps > w * h / 4);  // the course view shows the box and some of the void around it
  CHECK(lit > steps / 2);
}

TEST_CASE("several lights, several samples each: every shadow ray is listed under the light sample it tests",
          "[debugger][part3]") {
  const int w = 12, h = 9;
  const Scene scene = small_scene("CBlights.dae", w, h);
  RenderOptions o = options(4, w, h, 1, 2, 9);
  o.light_samples = 3;
  const auto geometry = debug::make_geometry(scene, o);
  int traced = 0, skipped = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const debug::PathRecord rec = debug::record_path(scene, *geometry, o, x, y, 0);
      REQUIRE(rec.ok());
      for (const debug::PathStep& st : rec.steps) {
        INFO("pixel (" << x << ", " << y << ") bounce " << st.bounce);
        CHECK(st.other_shadow_rays.empty());
        // Two area lights at -l 3 and two point lights at one sample each.
        CHECK(st.light_samples.size() == 8);
        for (const debug::LightSampleStep& l : st.light_samples) {
          const bool can_contribute = l.sample.pdf > 0 && l.cos_theta > 0;
          CHECK(l.shadow_traced == can_contribute);
          if (!l.shadow_traced) {
            ++skipped;
            continue;
          }
          ++traced;
          CHECK(same_bits(l.shadow_ray.o, st.point));
          CHECK(same_bits(l.shadow_ray.d, l.sample.wi));
          CHECK(l.shadow_ray.max_t == l.sample.distance - kRayEpsilon);
        }
      }
    }
  CHECK(traced > 0);
  CHECK(skipped > 0);  // points on the lights' backing plates and above them
}

TEST_CASE("each light sample is the one the build took: an untraced sample is one the estimator skips",
          "[debugger][part3]") {
  // The course's view of CBspheres_lambertian at 480x360, -s 64 -m 5 (part
  // 5): pixels where the first light sample of a bounce was skipped (below
  // the surface). Reconstructed from the numbers drawn, it came out with
  // the numbers swapped: cos theta 0.47, pdf 3.05, "not traced", which the
  // reference estimator never does to a sample it could trace.
  Scene scene = load_collada(project_scene("CBspheres_lambertian.dae"));
  RenderOptions o = options(5, 480, 360, 64, 5, 0);
  configure_camera(scene.camera, o);
  const auto geometry = debug::make_geometry(scene, o);
  int samples = 0, skipped = 0;
  std::vector<std::pair<int, int>> pixels = {{168, 109}, {130, 123}, {155, 114}};
  for (int y = 100; y < 130; y += 3) pixels.push_back({150, y});  // a column across the spheres
  for (const auto& [x, y] : pixels) {
    const debug::PathRecord rec = debug::record_path(scene, *geometry, o, x, y, 0);
    REQUIRE(rec.ok());
    CHECK(rec.exact);
    for (const debug::PathStep& st : rec.steps)
      for (const debug::LightSampleStep& l : st.light_samples) {
        INFO("pixel (" << x << ", " << y << ") bounce " << st.bounce << ": cos theta " << l.cos_theta << ", pdf "
                       << l.sample.pdf << ", " << l.verdict);
        ++samples;
        const bool can_contribute = l.sample.pdf > 0 && l.cos_theta > 0 && l.sample.distance > 2 * kRayEpsilon;
        CHECK(l.shadow_traced == can_contribute);
        CHECK(l.verdict != "not traced");
        if (!l.shadow_traced) {
          ++skipped;
          CHECK((l.verdict == "below the surface" || l.verdict == "zero pdf"));
          CHECK((l.contribution.x == 0 && l.contribution.y == 0 && l.contribution.z == 0));
        }
      }
  }
  CHECK(samples > 20);
  CHECK(skipped > 0);
}

TEST_CASE("Russian-roulette draws: one per bounce that plays, the one that ends a path is >= 0.7",
          "[debugger][part4]") {
  const int w = 12, h = 9;
  const Scene scene = small_scene("CBlights.dae", w, h);
  for (bool rr : {true, false}) {
    RenderOptions o = options(4, w, h, 4, 8, 41);
    o.russian_roulette = rr;
    const auto geometry = debug::make_geometry(scene, o);
    int played = 0, survived = 0, died = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int s = 0; s < o.samples_per_pixel; ++s) {
          const debug::PathRecord rec = debug::record_path(scene, *geometry, o, x, y, s);
          REQUIRE(rec.ok());
          for (size_t k = 0; k < rec.steps.size(); ++k) {
            const debug::PathStep& st = rec.steps[k];
            INFO("pixel (" << x << ", " << y << ") sample " << s << " step " << k);
            CHECK(st.roulette_applies == (rr && k > 0 && st.depth > 1));
            if (!st.roulette_applies) {
              CHECK(st.roulette_draws.empty());
              continue;
            }
            ++played;
            REQUIRE(st.roulette_draws.size() == 1);
            if (st.bsdf_sampled) {
              ++survived;
              CHECK(st.roulette_draws[0] < kContinueProbability);
            } else {
              ++died;
              CHECK(st.roulette_draws[0] >= kContinueProbability);
              CHECK(k + 1 == rec.steps.size());
            }
          }
        }
    INFO((rr ? "Russian roulette" : "--no-rr") << ": " << played << " played, " << survived << " survived");
    if (rr) {
      CHECK(survived > 0);
      CHECK(died > 0);
    } else {
      CHECK(played == 0);
    }
  }
}

TEST_CASE("recording is off outside record_path and leaves renders unchanged", "[debugger]") {
  const int w = 12, h = 9;
  const Scene scene = small_scene("CBlights.dae", w, h);
  const RenderOptions o = options(5, w, h, 8, 5, 51);
  const RenderResult before = render_scene(scene, o);
  const auto geometry = debug::make_geometry(scene, o);
  CHECK(active_path_recorder() == nullptr);
  const debug::PathRecord rec = debug::record_path(scene, *geometry, o, 4, 4, 0);
  CHECK(rec.ok());
  CHECK(active_path_recorder() == nullptr);
  const RenderResult after = render_scene(scene, o);
  REQUIRE(before.image.pixels.size() == after.image.pixels.size());
  int same = 0;
  for (size_t i = 0; i < before.image.pixels.size(); ++i) same += same_bits(before.image.pixels[i], after.image.pixels[i]);
  CHECK(same == int(before.image.pixels.size()));
}

TEST_CASE("a sample that adaptive sampling did not take is an input error", "[debugger][part5]") {
  const int w = 10, h = 8;
  const Scene scene = small_scene("CBlights.dae", w, h);
  RenderOptions o = options(5, w, h, 32, 3, 61);
  o.adaptive_batch = 4;
  o.adaptive_tolerance = 0.5;
  const RenderResult render = render_scene(scene, o);
  const auto geometry = debug::make_geometry(scene, o);
  int checked = 0;
  for (int y = 0; y < h && checked == 0; ++y)
    for (int x = 0; x < w && checked == 0; ++x) {
      const int taken = int(render.image.samples[render.image.index(x, y)]);
      if (taken >= o.samples_per_pixel) continue;
      CHECK(debug::record_path(scene, *geometry, o, x, y, taken - 1).ok());
      CHECK_THROWS_AS(debug::record_path(scene, *geometry, o, x, y, taken), debug::InputError);
      ++checked;
    }
  CHECK(checked == 1);
}

namespace {

// Geometry standing in for a student's that reaches a TODO stub.

class StubbedGeometry final : public Intersector {
 public:
  explicit StubbedGeometry(const Intersector& inner) : inner_(inner) {}
  bool intersect(Ray& r, Hit* hit) const override {
    todo_once("Part 2: a stubbed traversal (test)");
    return inner_.intersect(r, hit);
  }
  bool occluded(const Ray& r) const override { return inner_.occluded(r); }

 private:
  const Intersector& inner_;
};

}  // namespace

TEST_CASE("failing code gives a result naming where it failed, and TODO stubs are listed", "[debugger]") {
  const int w = 8, h = 6;
  const Scene scene = small_scene("CBlights.dae", w, h);
  const RenderOptions o = options(4, w, h, 1, 3, 71);
  const ThrowingGeometry throwing;
  const debug::PathRecord failed = debug::record_path(scene, throwing, o, 2, 2, 0);
  CHECK(!failed.ok());
  CHECK(failed.error.find("closest-hit or shadow query") != std::string::npos);
  CHECK(failed.error.find("node index out of range") != std::string::npos);
  CHECK(parse_json(failed.to_json(), "a failed path record").str("error") == failed.error);
  CHECK(active_path_recorder() == nullptr);

  const auto geometry = debug::make_geometry(scene, o);
  const StubbedGeometry stubbed(*geometry);
  for (int round = 0; round < 2; ++round) {  // listed every time, not only the first
    const debug::PathRecord rec = debug::record_path(scene, stubbed, o, 2, 2, 0);
    INFO("round " << round);
    CHECK(rec.ok());
    REQUIRE(rec.todos.size() == 1);
    CHECK(rec.todos[0] == "TODO: implement Part 2: a stubbed traversal (test)");
    // The path is said to be the stubs': in why it ended and in a note.
    CHECK(rec.end.find("(a stubbed traversal is still a stub)") != std::string::npos);
    CHECK(std::find(rec.notes.begin(), rec.notes.end(),
                    "the part's functions are still stubs (a stubbed traversal): this path is what their stand-ins "
                    "do, not what the assignment asks for") != rec.notes.end());
  }
}

TEST_CASE("record_path refuses absurd input with a one-line InputError", "[debugger]") {
  const int w = 8, h = 6;
  const Scene scene = small_scene("CBlights.dae", w, h);
  const RenderOptions good = options(4, w, h, 4, 3, 1);
  const auto geometry = debug::make_geometry(scene, good);
  const auto refused = [&](const RenderOptions& o, int x, int y, int s, const std::string& mentions) {
    INFO("pixel (" << x << ", " << y << ") sample " << s << ", expecting a message about " << mentions);
    try {
      debug::record_path(scene, *geometry, o, x, y, s);
      FAIL("accepted");
    } catch (const debug::InputError& e) {
      const std::string m = e.what();
      INFO(m);
      CHECK(m.find('\n') == std::string::npos);
      CHECK(m.find(mentions) != std::string::npos);
    }
  };
  refused(good, w, 0, 0, "outside");
  refused(good, 0, -1, 0, "outside");
  refused(good, 0, 0, 4, "sample index 4");
  refused(good, 0, 0, -1, "sample index -1");
  RenderOptions o = good;
  o.part = 6;
  refused(o, 0, 0, 0, "part");
  o.part = 0;
  refused(o, 0, 0, 0, "part");
  o = good;
  o.width = 2 * w;
  refused(o, 0, 0, 0, "configure_camera");
  o = good;
  o.max_depth = -1;
  refused(o, 0, 0, 0, "-m");
  o = good;
  o.light_samples = 0;
  refused(o, 0, 0, 0, "-l");
}
