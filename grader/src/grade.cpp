#include "grade.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include "image_io.h"
#include "pictures.h"
#include "text.h"

namespace grader {

namespace fs = std::filesystem;

const char* verdict_name(Verdict v) {
  switch (v) {
    case Verdict::Passed: return "passed";
    case Verdict::Failed: return "failed";
    case Verdict::Error: return "error";
  }
  return "?";
}

namespace {

// Partial credit for an image that fails the test: half the points when
// its relMSE is at the noise level, falling linearly to none at 0.05 above
// it, and none at all when its mean radiance is off by more than 10 % (a
// black image of a dim scene has a small relMSE, yet is simply wrong).
// Structural failures (crash, missing or NaN output) score nothing.
double partial_credit(const ImageScore& s, double points) {
  if (std::fabs(s.mean_candidate - s.mean_reference) > 0.1 * std::fabs(s.mean_reference)) return 0.0;
  const double excess = std::max(0.0, s.relmse - s.relmse_expected);
  return 0.5 * points * std::clamp(1.0 - excess / 0.05, 0.0, 1.0);
}

std::string join_command(const Case& c, int part, uint64_t seed) {
  std::string s = "pathtracer --part " + std::to_string(part);
  for (const std::string& o : c.options) s += " " + o;
  return s + " --seed " + std::to_string(seed) + " " + c.scene;
}

}  // namespace

namespace {

// "Part 3 not implemented: TODO estimate_direct_lighting_importance" from
// the TODO lines that doom a case of part `part` (todo_dooms), or "".
std::string not_implemented(const std::vector<std::string>& todo, int part) {
  std::map<int, std::vector<std::string>> missing;  // part -> what
  for (const std::string& t : todo) {
    const int p = todo_part(t);
    if (!todo_dooms(p, part)) continue;
    // "TODO: implement Part 1: generate_ray (stages/...)" -> "generate_ray"
    std::string what = t.substr(t.find(':', t.find("Part ")) + 1);
    what = what.substr(what.find_first_not_of(' '));
    what = what.substr(0, what.find(" ("));
    std::vector<std::string>& list = missing[p];
    if (std::find(list.begin(), list.end(), what) == list.end()) list.push_back(what);
  }
  if (missing.empty()) return "";
  std::string which = missing.size() == 1 ? "Part " : "Parts ", details;
  size_t i = 0;
  for (const auto& [p, list] : missing) {
    which += (i == 0 ? "" : i + 1 == missing.size() ? " and " : ", ") + std::to_string(p);
    std::string names;
    for (const std::string& n : list) names += (names.empty() ? "" : ", ") + n;
    details += (i == 0 ? "" : "; ") + (missing.size() > 1 ? "Part " + std::to_string(p) + ": " : std::string()) + names;
    ++i;
  }
  return which + " not implemented (TODO: " + details + ")";
}

// The costs of a render by kind of query, from its --stats-json.
struct QueryCosts {
  double closest_queries = 0, shadow_queries = 0, tests = 0;
  double closest_tests = 0, shadow_tests = 0;  // per query of that kind
};

QueryCosts query_costs(const Json& stats) {
  QueryCosts q;
  q.closest_queries = stats.num("closest_queries", 0);
  q.shadow_queries = stats.num("shadow_queries", 0);
  q.tests = stats.num("primitive_tests", 0);
  const double shadow = stats.num("shadow_primitive_tests", 0);
  if (q.closest_queries > 0) q.closest_tests = (q.tests - shadow) / q.closest_queries;
  if (q.shadow_queries > 0) q.shadow_tests = shadow / q.shadow_queries;
  return q;
}

}  // namespace

ScoreOptions case_score_options(const Case& c, const Reference& ref) {
  ScoreOptions so;
  so.deterministic = ref.deterministic;
  so.block_test = so.mean_test = !ref.deterministic;
  // Mitsuba's floor, 1e-4, is on the variance of one sample; ours is on
  // the variance of a whole render, so it is divided by the samples.
  so.variance_floor = 1e-4 / std::max(1, case_int_option(c, "-s", 1));
  return so;
}

// The step in which a rate case's sample rates move: one batch of -a over
// the -s maximum (a pixel takes a whole number of batches, or stops at -s).
double rate_step(const Case& c) {
  const int max_samples = std::max(1, case_int_option(c, "-s", 1));
  const int batch = std::max(1, case_int_option(c, "-a", 32));
  return std::min(1.0, double(batch) / max_samples);
}

CaseResult grade_case(const RunSettings& run, const std::string& reference_root, const Case& c, uint64_t seed,
                      const std::string& case_dir, const CostBounds& bounds) {
  CaseResult r;
  r.c = c;
  r.max_score = c.points;
  r.dir = case_dir;
  r.command = join_command(c, c.part, seed);
  const auto fail = [&](const std::string& why) {
    r.verdict = Verdict::Failed;
    r.score = 0;
    const std::string missing = not_implemented(r.todo, c.part);
    r.message = missing.empty() ? why : missing;
    return r;
  };

  Reference ref;
  std::string why;
  if (!load_reference(reference_root, c, &ref, &why)) {
    r.verdict = Verdict::Error;
    r.message = why;
    return r;
  }
  r.reference_seconds = ref.meta.num("render_seconds_median", -1);
  r.reference_tests_per_ray = ref.meta.num("tests_per_ray", -1);
  r.reference_closest_tests = ref.meta.num("closest_tests_per_query", -1);
  r.reference_shadow_tests = ref.meta.num("shadow_tests_per_query", -1);
  r.reference_shadow_per_query = ref.meta.num("shadow_per_query", -1);

  const bool want_rate = c.kind == CaseKind::Rate;
  RenderOutput out = render_case(run, c, c.part, seed, case_dir + "/render", want_rate);
  r.seconds = out.seconds;
  r.log = out.log;
  r.todo = out.todo;
  if (!out.ok) return fail(out.failure);
  if (out.has_stats) {
    r.render_seconds = out.stats.num("render_seconds", -1);
    if (out.stats.num("rays", 0) > 0) r.tests_per_ray = stat_ratio(out.stats, "primitive_tests", "rays");
    r.mrays_per_second = out.stats.num("mrays_per_second", -1);
    r.triangles = out.stats.num("triangles", -1);
    if (r.render_seconds > 0 && r.reference_seconds > 0) r.speed_ratio = r.render_seconds / r.reference_seconds;
  }

  // The image, against the reference.
  if (out.radiance.width != ref.mean.width || out.radiance.height != ref.mean.height)
    return fail("the reference is " + std::to_string(ref.mean.width) + " x " + std::to_string(ref.mean.height) +
                ": remake it");
  const ImageScore img = score_image(out.radiance, ref.mean, ref.variance, ref.runs, case_score_options(c, ref));
  r.relmse = img.relmse;
  r.metric = img.summary();
  try {
    save_picture(case_dir + "/candidate.png", radiance_picture(out.radiance));
    save_picture(case_dir + "/reference.png", radiance_picture(ref.mean));
    save_picture(case_dir + "/error.png",
                 error_picture(img.pixel_z, out.radiance.width, out.radiance.height, img.pixel_threshold));
  } catch (const std::exception&) {
    // Pictures for people only; the verdict does not depend on them.
  }

  std::vector<std::string> problems;
  if (!img.passed) {
    char buf[400];
    if (img.deterministic)
      std::snprintf(buf, sizeof buf,
                    "image differs from the reference: %d of %d pixel channels off by more than round-off (largest "
                    "difference %.3g); mean radiance %.4g vs %.4g",
                    img.channels_failed, img.channels_tested, img.max_abs_difference, img.mean_candidate,
                    img.mean_reference);
    else {
      std::string parts = std::to_string(img.channels_failed) + " of " + std::to_string(img.channels_tested) +
                          " pixel channels beyond " + fmt("|z| = %.2f", img.pixel_threshold);
      if (img.blocks_tested > 0)
        parts += ", " + std::to_string(img.blocks_failed) + " of " + std::to_string(img.blocks_tested) +
                 " blocks beyond " + fmt("|z| = %.2f", img.block_threshold);
      if (img.mean_tested)
        parts += fmt(", image mean |z| = %.1f", img.max_mean_z()) + fmt(" (limit %.2f)", img.mean_threshold);
      std::snprintf(buf, sizeof buf, "image differs from the reference: %s; mean radiance %.4g vs %.4g", parts.c_str(),
                    img.mean_candidate, img.mean_reference);
    }
    problems.push_back(buf);
  }
  double credit = img.passed ? c.points : partial_credit(img, c.points);

  if (c.kind == CaseKind::Rate) {
    ScoreOptions ro;
    ro.variance_floor = 1e-3;  // rates move in steps of one batch
    ro.pixel_slack = rate_step(c);
    const ImageScore rate = score_image(out.rate, ref.rate_mean, ref.rate_variance, ref.runs, ro);
    r.metric += "; rate: " + rate.summary();
    if (!rate.passed) {
      problems.push_back("sample-rate image differs: " + std::to_string(rate.channels_failed) + " of " +
                         std::to_string(rate.channels_tested) + " pixels beyond " +
                         fmt("|z| = %.2f, ", rate.pixel_threshold) + std::to_string(rate.blocks_failed) + " of " +
                         std::to_string(rate.blocks_tested) + " blocks off, " +
                         fmt("mean |z| = %.1f; ", rate.max_mean_z()) + fmt("mean rate %.3f vs ", rate.mean_candidate) +
                         fmt("%.3f", rate.mean_reference));
      credit = std::min(credit, partial_credit(rate, c.points));
    }
  }

  // Costs, from part 2 on (part 1 tests every primitive by design): per
  // kind of query, so that a BVH that culls for camera rays but not for
  // shadow rays shows, and shadow rays per closest-hit query (one per delta
  // light, none for a light below the surface).
  if (c.part >= 2) {
    if (!out.has_stats || out.stats.num("closest_queries", 0) <= 0) {
      problems.push_back("no ray counts (--stats-json stats.json)");
      credit = 0;
    } else {
      const QueryCosts q = query_costs(out.stats);
      r.closest_tests = q.closest_tests;
      if (q.shadow_queries > 0) r.shadow_tests = q.shadow_tests;
      r.shadow_per_query = q.shadow_queries / q.closest_queries;
      const auto limit = [&](double reference) { return bounds.tests_factor * reference + bounds.tests_slack; };
      if (q.tests <= 0) {
        problems.push_back("no intersection tests counted: every primitive test counts into thread_ray_stats() "
                           "(see the part 2 contract)");
        credit = 0;
      }
      if (r.reference_closest_tests >= 0 && q.closest_tests > limit(r.reference_closest_tests)) {
        problems.push_back(fmt("%.1f intersection tests per camera or bounce ray, ", q.closest_tests) +
                           fmt("more than %.0fx the reference's ", bounds.tests_factor) +
                           fmt("%.2f: the BVH does not cull", r.reference_closest_tests));
        credit = 0;
      }
      if (r.reference_shadow_tests >= 0 && q.shadow_queries > 0 && q.shadow_tests > limit(r.reference_shadow_tests)) {
        problems.push_back(fmt("%.1f intersection tests per shadow ray, ", q.shadow_tests) +
                           fmt("more than %.0fx the reference's ", bounds.tests_factor) +
                           fmt("%.2f: the occlusion query does not cull (boxes beyond the light, or every "
                               "primitive tested)",
                               r.reference_shadow_tests));
        credit = 0;
      }
      if (r.reference_shadow_per_query > 0 && r.shadow_per_query > bounds.shadow_factor * r.reference_shadow_per_query) {
        problems.push_back(fmt("%.2f shadow rays per closest-hit query, ", r.shadow_per_query) +
                           fmt("the reference needs %.2f: a delta light needs one sample, not -l, and a light "
                               "below the surface none",
                               r.reference_shadow_per_query));
        credit = 0;
      }
      r.metric += fmt("; tests per query %.2f", q.closest_tests) + fmt(" (ref %.2f)", r.reference_closest_tests);
      if (q.shadow_queries > 0)
        r.metric += fmt(", per shadow ray %.2f", q.shadow_tests) + fmt(" (ref %.2f)", r.reference_shadow_tests) +
                    fmt("; %.2f shadow rays per query", r.shadow_per_query) +
                    fmt(" (ref %.2f)", r.reference_shadow_per_query);
    }
  }

  if (c.kind == CaseKind::Speedup) {
    RenderOutput p1 = render_case(run, c, 1, seed, case_dir + "/part1", false);
    r.part1_seconds = p1.ok && p1.has_stats ? p1.stats.num("render_seconds", -1) : -1;
    r.seconds += p1.seconds;
    for (const std::string& t : p1.todo)
      if (std::find(r.todo.begin(), r.todo.end(), t) == r.todo.end()) r.todo.push_back(t);
    if (!p1.ok) {
      problems.push_back("the --part 1 (no BVH) render failed: " + p1.failure);
      credit = 0;
    } else if (r.part1_seconds <= 0 || r.render_seconds <= 0 || r.tests_per_ray <= 0) {
      problems.push_back("no render times or test counts (--stats-json stats.json)");
      credit = 0;
    } else {
      // The verdict rests on the work saved (intersection tests per ray),
      // which no machine load can change; the time speed-up of a render
      // of a few milliseconds is shown but is too noisy to fail anyone on.
      const double p1_tests = stat_ratio(p1.stats, "primitive_tests", "rays");
      const double work_ratio = p1_tests / r.tests_per_ray;
      r.speedup = r.part1_seconds / r.render_seconds;
      r.metric += fmt("; BVH speed-up %.0fx", r.speedup) + fmt(" (%.0fx fewer tests per ray)", work_ratio);
      if (work_ratio < bounds.min_speedup) {
        problems.push_back(fmt("the BVH saves too little: %.1fx fewer intersection tests per ray ", work_ratio) +
                           fmt("than testing every primitive (at least %.0fx expected)", bounds.min_speedup));
        credit = 0;
      }
    }
  }

  if (problems.empty()) {
    r.verdict = Verdict::Passed;
    r.score = c.points;
    r.message = "matches the reference";
    return r;
  }
  r.verdict = Verdict::Failed;
  r.score = credit;
  // An unfinished part is the news: say that first, not pixel statistics.
  const std::string missing = not_implemented(r.todo, c.part);
  if (!missing.empty()) {
    r.score = 0;
    r.message = missing;
    return r;
  }
  r.message = problems[0];
  for (size_t i = 1; i < problems.size(); ++i) r.message += "; " + problems[i];
  return r;
}

bool not_implemented(const CaseResult& r) {
  return std::any_of(r.todo.begin(), r.todo.end(),
                     [&](const std::string& t) { return todo_dooms(todo_part(t), r.c.part); });
}

std::string case_result_json(const CaseResult& r) {
  std::string s = "{\n";
  const auto field = [&](const char* k, const std::string& v, bool last = false) {
    s += std::string("  \"") + k + "\": " + v + (last ? "\n" : ",\n");
  };
  field("name", json_quote(r.c.name));
  field("part", std::to_string(r.c.part));
  field("kind", json_quote(kind_name(r.c.kind)));
  field("verdict", json_quote(verdict_name(r.verdict)));
  field("score", json_number(r.score));
  field("max_score", json_number(r.max_score));
  field("message", json_quote(r.message));
  field("metric", json_quote(r.metric));
  field("relmse", json_number(r.relmse));
  field("seconds", json_number(r.seconds));
  field("render_seconds", json_number(r.render_seconds));
  field("reference_seconds", json_number(r.reference_seconds));
  field("speed_ratio", json_number(r.speed_ratio));
  field("tests_per_ray", json_number(r.tests_per_ray));
  field("reference_tests_per_ray", json_number(r.reference_tests_per_ray));
  field("closest_tests", json_number(r.closest_tests));
  field("reference_closest_tests", json_number(r.reference_closest_tests));
  field("shadow_tests", json_number(r.shadow_tests));
  field("reference_shadow_tests", json_number(r.reference_shadow_tests));
  field("shadow_per_query", json_number(r.shadow_per_query));
  field("reference_shadow_per_query", json_number(r.reference_shadow_per_query));
  {
    std::string list = "[";
    for (size_t i = 0; i < r.todo.size(); ++i) list += (i ? ", " : "") + json_quote(r.todo[i]);
    field("todo", list + "]");
  }
  field("mrays_per_second", json_number(r.mrays_per_second));
  field("triangles", json_number(r.triangles));
  field("part1_seconds", json_number(r.part1_seconds));
  field("speedup", json_number(r.speedup));
  field("command", json_quote(r.command));
  field("scene", json_quote(r.c.scene));
  field("dir", json_quote(fs::absolute(r.dir).string()));
  field("log", json_quote(r.log), true);
  return s + "}\n";
}

bool case_result_from_json(const Json& j, CaseResult* r) {
  if (j.type != Json::Type::Object || j.str("name").empty()) return false;
  r->c.name = j.str("name");
  r->c.part = int(j.num("part", 0));
  parse_kind(j.str("kind"), &r->c.kind);
  r->c.scene = j.str("scene");
  const std::string v = j.str("verdict");
  r->verdict = v == "passed" ? Verdict::Passed : v == "failed" ? Verdict::Failed : Verdict::Error;
  r->score = j.num("score", 0);
  r->max_score = j.num("max_score", 0);
  r->c.points = r->max_score;
  r->message = j.str("message");
  r->metric = j.str("metric");
  r->relmse = j.num("relmse", -1);
  r->seconds = j.num("seconds", 0);
  r->render_seconds = j.num("render_seconds", -1);
  r->reference_seconds = j.num("reference_seconds", -1);
  r->speed_ratio = j.num("speed_ratio", -1);
  r->tests_per_ray = j.num("tests_per_ray", -1);
  r->reference_tests_per_ray = j.num("reference_tests_per_ray", -1);
  r->closest_tests = j.num("closest_tests", -1);
  r->reference_closest_tests = j.num("reference_closest_tests", -1);
  r->shadow_tests = j.num("shadow_tests", -1);
  r->reference_shadow_tests = j.num("reference_shadow_tests", -1);
  r->shadow_per_query = j.num("shadow_per_query", -1);
  r->reference_shadow_per_query = j.num("reference_shadow_per_query", -1);
  r->todo.clear();
  if (const Json* t = j.get("todo"))
    for (const Json& e : t->array) r->todo.push_back(e.string);
  r->mrays_per_second = j.num("mrays_per_second", -1);
  r->triangles = j.num("triangles", -1);
  r->part1_seconds = j.num("part1_seconds", -1);
  r->speedup = j.num("speedup", -1);
  r->command = j.str("command");
  r->dir = j.str("dir");
  r->log = j.str("log");
  return true;
}

}  // namespace grader
