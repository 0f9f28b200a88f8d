// What the path inspector's tests share: exact comparisons, a colour as
// text, the options of a small render, a project scene in the course's
// view, geometry that throws (a student's failing code), and the replay
// of every sample of a render checked against the render (check_adds_up).
#pragma once
#include <catch2/catch.hpp>
#include <algorithm>
#include <cstring>
#include <sstream>
#include <stdexcept>
#include <string>

#include "common/collada.h"
#include "pathtracer/render_job.h"
#include "viewer/debugger/debugger.h"
#include "common/intersector.h"
#include "pathtracer/options.h"
#include "tests/statistics/analytic_scenes.h"
#include "tests/support.h"

namespace pt::test::path {

inline bool same_bits(const Color& a, const Color& b) {
  const float x[3] = {a.x, a.y, a.z}, y[3] = {b.x, b.y, b.z};
  return std::memcmp(x, y, sizeof x) == 0;
}

inline bool same_bits(const Vec3& a, const Vec3& b, float s, float t) {
  return same_bits(a, b) && std::memcmp(&s, &t, sizeof s) == 0;
}

inline std::string show(const Color& c) {
  std::ostringstream o;
  o.precision(9);
  o << "(" << c.x << ", " << c.y << ", " << c.z << ")";
  return o.str();
}

inline RenderOptions options(int part, int w, int h, int spp, int max_depth, uint64_t seed) {
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

inline Scene small_scene(const std::string& name, int w, int h) {
  Scene s = load_collada(project_scene(name));
  fit_course_view(s.camera, w, h);
  return s;
}

// Geometry standing in for a student's that throws.
class ThrowingGeometry final : public Intersector {
 public:
  bool intersect(Ray&, Hit*) const override { throw std::runtime_error("node index out of range"); }
  bool occluded(const Ray&) const override { return false; }
};

// What the replays of one configuration showed, to check that the test saw
// the features it claims to cover.
struct Coverage {
  int records = 0, exact = 0, pixels = 0, pixels_equal = 0;
  int longest = 0;               // most steps in one path
  int roulette_deaths = 0;       // paths ended by a draw >= 0.7
  int blocked = 0, lit = 0;      // light samples
  int probes = 0;                // hemisphere samples
  int escaped = 0;               // camera rays that hit nothing
  int delta = 0;                 // steps at a delta BSDF (mirror, glass; part 6)
  int reflected = 0, refracted = 0;  // their BSDF samples
  int reached = 0;               // delta steps whose bounce brought light (counted and not black)
  int microfacet = 0;            // BSDF samples at a microfacet surface (part 7)
};

// Renders the whole image with the command line's render_scene, replays
// every sample of every pixel and checks (1) each record adds up exactly,
// (2) the average of the replayed samples is exactly the rendered pixel
// and (3) part 5's sample counts agree.
inline Coverage check_adds_up(const Scene& scene, const RenderOptions& o, const std::string& what) {
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
          c.delta += st.delta ? 1 : 0;
          if (st.delta && st.bsdf_sampled) (st.bsdf_scatter == "refracted" ? c.refracted : c.reflected) += 1;
          c.reached += st.reached_counted && !is_black(st.reached) ? 1 : 0;
          c.microfacet += st.bsdf_sampled && st.bsdf_model == "microfacet" ? 1 : 0;
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

}  // namespace pt::test::path
