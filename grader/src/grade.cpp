#include "grader/src/grade.h"

#include <algorithm>
#include <map>

#include "grader/src/pictures.h"

namespace grader {

std::string not_implemented_message(const std::vector<std::string>& todo, int part) {
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

bool doomed_by_todo(const CaseResult& r) {
  return std::any_of(r.todo.begin(), r.todo.end(),
                     [&](const std::string& t) { return todo_dooms(todo_part(t), r.c.part); });
}

ScoreOptions case_score_options(const Case& c, const Reference& ref) {
  ScoreOptions so;
  so.deterministic = ref.deterministic;
  so.block_test = so.mean_test = !ref.deterministic;
  // Mitsuba's floor, 1e-4, is on the variance of one sample; ours is on
  // the variance of a whole render, so it is divided by the samples.
  so.variance_floor = 1e-4 / std::max(1, case_int_option(c, "-s", 1));
  return so;
}

namespace {

std::string join_command(const Case& c, int part, uint64_t seed) {
  std::string s = "pathtracer --part " + std::to_string(part);
  for (const std::string& o : c.options) s += " " + o;
  return s + " --seed " + std::to_string(seed) + " " + c.scene;
}

// The step in which a rate case's sample rates move: one batch of -a over
// the -s maximum (a pixel takes a whole number of batches, or stops at -s).
double rate_step(const Case& c) {
  const int max_samples = std::max(1, case_int_option(c, "-s", 1));
  const int batch = std::max(1, case_int_option(c, "-a", 32));
  return std::min(1.0, double(batch) / max_samples);
}

// The figures of the render and of the reference that the reports show.
void record_figures(const RenderOutput& out, const Reference& ref, CaseResult* r) {
  r->reference_seconds = ref.meta.num("render_seconds_median", -1);
  r->reference_tests_per_ray = ref.meta.num("tests_per_ray", -1);
  r->reference_closest_tests = ref.meta.num("closest_tests_per_query", -1);
  r->reference_shadow_tests = ref.meta.num("shadow_tests_per_query", -1);
  r->reference_shadow_per_query = ref.meta.num("shadow_per_query", -1);
  if (!out.has_stats) return;
  r->render_seconds = out.stats.num("render_seconds", -1);
  if (out.stats.num("rays", 0) > 0) r->tests_per_ray = stat_ratio(out.stats, "primitive_tests", "rays");
  r->mrays_per_second = out.stats.num("mrays_per_second", -1);
  r->triangles = out.stats.num("triangles", -1);
  if (r->render_seconds > 0 && r->reference_seconds > 0) r->speed_ratio = r->render_seconds / r->reference_seconds;
}

// Pictures for people only; the verdict does not depend on them.
void save_pictures(const std::string& case_dir, const RenderOutput& out, const Reference& ref, const ImageScore& img) {
  try {
    save_picture(case_dir + "/candidate.png", radiance_picture(out.radiance));
    save_picture(case_dir + "/reference.png", radiance_picture(ref.mean));
    save_picture(case_dir + "/error.png",
                 error_picture(img.pixel_z, out.radiance.width, out.radiance.height, img.pixel_threshold));
  } catch (const std::exception&) {
  }
}

// The verdict from the checks: passed when none found a problem, else
// failed with the smallest credit any of them leaves, and the problems as
// the message; an unfinished part is the news then, not pixel statistics.
void decide(const std::vector<Check>& checks, CaseResult* r) {
  std::vector<std::string> problems;
  double credit = r->c.points;
  for (const Check& k : checks) {
    problems.insert(problems.end(), k.problems.begin(), k.problems.end());
    credit = std::min(credit, k.credit);
  }
  if (problems.empty()) {
    r->verdict = Verdict::Passed;
    r->score = r->c.points;
    r->message = "matches the reference";
    return;
  }
  r->verdict = Verdict::Failed;
  const std::string missing = not_implemented_message(r->todo, r->c.part);
  r->score = missing.empty() ? credit : 0;
  r->message = missing;
  if (!missing.empty()) return;
  r->message = problems[0];
  for (size_t i = 1; i < problems.size(); ++i) r->message += "; " + problems[i];
}

// The sample-rate image of an adaptive case, scored as an image of its own.
Check rate_check(const Case& c, const Reference& ref, const RenderOutput& out) {
  ScoreOptions ro;
  ro.channels = 1;           // the rate is in every channel
  ro.variance_floor = 1e-3;  // rates move in steps of one batch
  ro.pixel_slack = rate_step(c);
  return check_rate_image(score_image(out.rate, ref.rate_mean, ref.rate_variance, ref.runs, ro), c.points);
}

// Costs, from part 2 on (part 1 tests every primitive by design): per
// kind of query, so that a BVH that culls for camera rays but not for
// shadow rays shows, and shadow rays per closest-hit query (one per delta
// light, none for a light below the surface).
Check cost_check(const Case& c, const RenderOutput& out, const CostBounds& bounds, CaseResult* r) {
  const QueryCosts reference{r->reference_closest_tests, r->reference_shadow_tests, r->reference_shadow_per_query};
  QueryCosts measured;
  Check k = check_costs(out.has_stats ? &out.stats : nullptr, reference, bounds, c.points, &measured);
  r->closest_tests = measured.closest_tests;
  r->shadow_tests = measured.shadow_tests;
  r->shadow_per_query = measured.shadow_per_query;
  return k;
}

// The BVH's speed-up: the same case rendered with --part 1, in this run.
Check speedup_check(const RunSettings& run, const Case& c, uint64_t seed, const std::string& case_dir,
                    const CostBounds& bounds, CaseResult* r) {
  const RenderOutput p1 = render_case(run, c, 1, seed, case_dir + "/part1", false);
  r->seconds += p1.seconds;
  for (const std::string& t : p1.todo)
    if (std::find(r->todo.begin(), r->todo.end(), t) == r->todo.end()) r->todo.push_back(t);
  return check_speedup(p1, r->render_seconds, r->tests_per_ray, bounds, c.points, &r->part1_seconds, &r->speedup);
}

}  // namespace

CaseResult grade_case(const RunSettings& run, const std::string& reference_root, const Case& c, uint64_t seed,
                      const std::string& case_dir, const CostBounds& bounds) {
  CaseResult r;
  r.c = c;
  r.max_score = c.points;
  r.dir = case_dir;
  r.command = join_command(c, c.part, seed);
  // A render that cannot be judged at all scores nothing.
  const auto fail = [&](const std::string& why) {
    r.verdict = Verdict::Failed;
    r.score = 0;
    const std::string missing = not_implemented_message(r.todo, c.part);
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
  RenderOutput out = render_case(run, c, c.part, seed, case_dir + "/render", c.kind == CaseKind::Rate);
  r.seconds = out.seconds;
  r.log = out.log;
  r.todo = out.todo;
  record_figures(out, ref, &r);
  if (!out.ok) return fail(out.failure);
  if (out.radiance.width != ref.mean.width || out.radiance.height != ref.mean.height)
    return fail("the reference is " + std::to_string(ref.mean.width) + " x " + std::to_string(ref.mean.height) +
                ": remake it");

  std::vector<Check> checks;
  const ImageScore img = score_image(out.radiance, ref.mean, ref.variance, ref.runs, case_score_options(c, ref));
  r.relmse = img.relmse;
  save_pictures(case_dir, out, ref, img);
  checks.push_back(check_image(img, c.points));

  if (c.kind == CaseKind::Rate) checks.push_back(rate_check(c, ref, out));
  if (c.part >= 2) checks.push_back(cost_check(c, out, bounds, &r));
  if (c.kind == CaseKind::Speedup) checks.push_back(speedup_check(run, c, seed, case_dir, bounds, &r));

  for (const Check& k : checks) r.metric += k.metric;
  decide(checks, &r);
  return r;
}

}  // namespace grader
