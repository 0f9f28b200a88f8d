// The path inspector's steps (viewer/debugger): light samples and their
// shadow rays as the build took them, Russian-roulette draws, recording off
// in normal renders, and what a failing, stubbed or refused replay gives.
// Deterministic: fixed seeds, exact comparisons.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/collada.h"
#include "common/json.h"
#include "common/path_recorder.h"
#include "common/todo.h"
#include "pathtracer/render_job.h"
#include "stages/part3_direct_lighting/direct_lighting.h"
#include "stages/part4_global_illumination/global_illumination.h"
#include "tests/debugger/path_support.h"
#include "viewer/debugger/debugger.h"

using namespace pt;
using namespace pt::test;
using namespace pt::test::path;

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
          const bool can_contribute = !is_black(l.sample.radiance) && l.cos_theta > 0;
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
        const bool can_contribute =
            !is_black(l.sample.radiance) && l.cos_theta > 0 && l.sample.distance > 2 * kRayEpsilon;
        CHECK(l.shadow_traced == can_contribute);
        CHECK(l.verdict != "not traced");
        if (!l.shadow_traced) {
          ++skipped;
          CHECK((l.verdict == "below the surface" || l.verdict == "no light (the back of the light)"));
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
  o.part = kPartsBuilt + 1;
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
