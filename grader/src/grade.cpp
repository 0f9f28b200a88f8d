#include "grader/src/grade.h"

#include <algorithm>
#include <cstdlib>
#include <map>

#include "grader/src/pictures.h"
#include "grader/src/probability_image.h"
#include "grader/src/signature.h"

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

ScoreOptions case_score_options(const Case& c, const Reference& ref, const Rules& rules) {
  ScoreOptions so;
  so.deterministic = ref.deterministic;
  so.block_test = so.mean_test = !ref.deterministic;
  // Mitsuba's floor, 1e-4, is on the variance of one sample; ours is on
  // the variance of a whole render, so it is divided by the samples.
  so.variance_floor = 1e-4 / std::max(1, case_int_option(c, "-s", 1));
  // The image's share of the run's false-failure budget, half to each test
  // whose false failures it bounds (the pixel test's are bounded by its
  // allowance of 0.25 % of the channels instead: under the model a correct
  // render fails about 0.01 of them).
  so.block_alpha = so.mean_alpha = 0.5 * rules.image_alpha();
  return so;
}

ScoreOptions case_score_options(const Case& c, const Reference& ref) { return case_score_options(c, ref, Rules()); }

namespace {

// The step in which a rate case's sample rates move: one batch of -a over
// the -s maximum (a pixel takes a whole number of batches, or stops at -s).
double rate_step(const Case& c) {
  const int max_samples = std::max(1, case_int_option(c, "-s", 1));
  const int batch = std::max(1, case_int_option(c, "-a", 32));
  return std::min(1.0, double(batch) / max_samples);
}

// What went wrong with a render that could not be judged, as a signature
// entry: failure_nan, failure_negative, failure_todo, failure_crash,
// failure_timeout, failure_exit or failure_output.
std::string failure_kind(const RenderOutput& out) {
  if (out.stopped_at_todo) return "failure_todo";
  if (out.child.timed_out) return "failure_timeout";
  if (out.child.signal != 0) return "failure_crash";
  if (!out.child.started || out.child.exit_code != 0) return "failure_exit";
  if (out.failure.find("NaN") != std::string::npos) return "failure_nan";
  if (out.failure.find("negative") != std::string::npos) return "failure_negative";
  return "failure_output";
}

// Cost ratios against the reference's figures, for the signature.
void add_cost_signature(const CaseResult& r, Signature* s) {
  const auto ratio = [&](const char* key, double mine, double ref) {
    if (mine >= 0 && ref > 0) (*s)[key] = mine / ref;
  };
  ratio("closest_tests_ratio", r.closest_tests, r.reference_closest_tests);
  ratio("shadow_tests_ratio", r.shadow_tests, r.reference_shadow_tests);
  ratio("shadow_rays_ratio", r.shadow_per_query, r.reference_shadow_per_query);
}

// The candidate's renders of a case, with their statistics summed.
struct Renders {
  std::vector<RenderOutput> outs;  // in seed order; the last one may have failed
  CandidateRenders radiance, rate;
  bool has_stats = false;
  Json stats;                      // counts and times summed over the renders
  bool ok() const { return !outs.empty() && outs.back().ok; }
};

// The counts of --stats-json that add up over renders; the rest are the
// first render's (the scene's triangles, ...).
void add_stats(const Json& one, Json* sum) {
  static const char* const kCounts[] = {"rays", "closest_queries", "shadow_queries", "primitive_tests",
                                        "shadow_primitive_tests", "node_visits", "shadow_node_visits",
                                        "render_seconds"};
  if (sum->type != Json::Type::Object) {
    *sum = one;
    return;
  }
  for (const char* key : kCounts) sum->set(key, pt::json_real(sum->num(key, 0) + one.num(key, 0)));
  const double seconds = sum->num("render_seconds", 0);
  if (seconds > 0) sum->set("mrays_per_second", pt::json_real(sum->num("rays", 0) / seconds * 1e-6));
}

// Renders the plan's renders one after another into case_dir/render,
// render_1, ...; stops at the first that fails.
Renders render_candidate(const RunSettings& run, const RenderPlan& plan, uint64_t seed, const std::string& case_dir,
                         CaseResult* r) {
  Renders rs;
  rs.radiance.share = plan.share;
  for (int k = 0; k < plan.renders; ++k) {
    const std::string dir = case_dir + (k == 0 ? "/render" : "/render_" + std::to_string(k));
    // A probability case's first render also writes the map's probability image.
    const Case rc = k == 0 ? with_probability_image(plan.c) : plan.c;
    RenderOutput out = render_case(run, rc, plan.c.part, candidate_seed(seed, k), dir, plan.c.kind == CaseKind::Rate);
    r->seconds += out.seconds;
    if (r->log.empty() || !out.ok) r->log = out.log;
    for (const std::string& t : out.todo)
      if (std::find(r->todo.begin(), r->todo.end(), t) == r->todo.end()) r->todo.push_back(t);
    if (out.ok) {
      rs.radiance.images.push_back(out.radiance);
      if (plan.c.kind == CaseKind::Rate) rs.rate.images.push_back(out.rate);
      if (out.has_stats) {
        add_stats(out.stats, &rs.stats);
        rs.has_stats = true;
      }
    }
    const bool failed = !out.ok;
    rs.outs.push_back(std::move(out));
    if (failed) break;
  }
  return rs;
}

// "pathtracer --part 3 ... --seed S scene" for the first render, and the
// others' seeds.
std::string join_command(const RenderPlan& plan, uint64_t seed) {
  std::string s = "pathtracer --part " + std::to_string(plan.c.part);
  for (const std::string& o : plan.c.options) s += " " + o;
  s += " --seed " + std::to_string(candidate_seed(seed, 0)) + " " + plan.c.scene;
  if (plan.renders > 1)
    s += " (and at seeds " + std::to_string(candidate_seed(seed, 1)) + " to " +
         std::to_string(candidate_seed(seed, plan.renders - 1)) + ": " + std::to_string(plan.renders) + " renders)";
  return s;
}

// The figures of the renders and of the reference that the reports show.
// Times are per render of the case's settings: the renders' sum, times
// each render's share of the case's samples.
void record_figures(const Renders& rs, double share, const Reference& ref, CaseResult* r) {
  r->reference_seconds = ref.meta.num("render_seconds_median", -1);
  r->reference_tests_per_ray = ref.meta.num("tests_per_ray", -1);
  r->reference_closest_tests = ref.meta.num("closest_tests_per_query", -1);
  r->reference_shadow_tests = ref.meta.num("shadow_tests_per_query", -1);
  r->reference_shadow_per_query = ref.meta.num("shadow_per_query", -1);
  if (!rs.has_stats) return;
  const double n = double(rs.radiance.images.size());
  const double per_case = share < 1.0 ? share * n : 1.0 / std::max(1.0, n);  // sum -> one render at the case's -s
  r->render_seconds = rs.stats.num("render_seconds", -1) * per_case;
  if (rs.stats.num("rays", 0) > 0) r->tests_per_ray = stat_ratio(rs.stats, "primitive_tests", "rays");
  r->mrays_per_second = rs.stats.num("mrays_per_second", -1);
  r->triangles = rs.stats.num("triangles", -1);
  if (r->render_seconds > 0 && r->reference_seconds > 0) r->speed_ratio = r->render_seconds / r->reference_seconds;
}

// Pictures for people only; the verdict does not depend on them.
void save_pictures(const std::string& case_dir, const ImageBuffer& candidate, const Reference& ref,
                   const ImageScore& img) {
  try {
    save_picture(case_dir + "/candidate.png", radiance_picture(candidate));
    save_picture(case_dir + "/reference.png", radiance_picture(ref.mean));
    save_picture(case_dir + "/error.png",
                 error_picture(img.pixel_z, candidate.width, candidate.height, img.pixel_threshold));
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

// The sample-rate images of an adaptive case, judged by the build's own
// noise. A less noisy estimator than the given one (multiple importance
// sampling of the lights) stops its pixels earlier, so a rate below the
// reference's is not wrong in itself: what the rule asks is a noise level,
// and where pixels stop early the build's own noise must be about the
// reference's there (check_stopped_noise). A rate above the reference's
// fails as a sample-rate image of its own (one-sided): a build that records
// more samples than it took cannot be told by its images from one whose
// estimator is noisier, and direct light's noise is part 3's to judge.
Check rate_check(const Case& c, const Reference& ref, const Renders& rs, const Rules& rules, Signature* signature) {
  ScoreOptions ro;
  ro.channels = 1;           // the rate is in every channel
  ro.variance_floor = 1e-3;  // rates move in steps of one batch
  ro.pixel_slack = rate_step(c);
  ro.upper_only = true;
  ro.block_alpha = ro.mean_alpha = 0.5 * rules.image_alpha();
  const ImageScore rate = score_renders(rs.rate, ref.rate_mean, ref.rate_variance, ref.runs, ro);
  if (rate.mean_reference > 0) (*signature)["rate_ratio"] = rate.mean_candidate / rate.mean_reference;
  if (rate.channels_tested > 0) (*signature)["rate_failed_fraction"] = double(rate.channels_failed) / rate.channels_tested;
  Check k = check_rate_image(rate, c.points, "the reference's: a rate above it fails");
  const double stopped = stopped_noise_ratio(rs.radiance, ref.variance, ref.rate_mean, rules.stopped_noise_cap);
  const Check noise = check_stopped_noise(stopped, rules.stopped_noise_bound, rules.noise_credit, c.points);
  k.metric += noise.metric;
  k.problems.insert(k.problems.end(), noise.problems.begin(), noise.problems.end());
  k.credit = std::min(k.credit, noise.credit);
  return k;
}

// Costs, from part 2 on (part 1 tests every primitive by design): per
// kind of query, against a plain binary BVH's on the same case, and
// shadow rays per closest-hit query (one per delta light, none for a
// light below the surface) against the reference's.
Check cost_check(const Case& c, const Renders& rs, const Rules& rules, CaseResult* r) {
  CostBaseline base;
  const auto plain = rules.plain_bvh.find(c.name);
  if (plain != rules.plain_bvh.end()) {
    base.tests = plain->second;
  } else {  // a case the plain BVH was not measured on
    base.plain = false;
    base.tests = QueryCosts{r->reference_closest_tests, r->reference_shadow_tests, -1};
  }
  base.reference_shadow_per_query = r->reference_shadow_per_query;
  QueryCosts measured;
  Check k = check_costs(rs.has_stats ? &rs.stats : nullptr, c.part, base, rules.costs, c.points, &measured);
  r->closest_tests = measured.closest_tests;
  r->shadow_tests = measured.shadow_tests;
  r->shadow_per_query = measured.shadow_per_query;
  return k;
}

// The BVH's speed-up: the same case rendered with --part 1, in this run.
Check speedup_check(const RunSettings& run, const Case& c, uint64_t seed, const std::string& case_dir,
                    const CostBounds& bounds, CaseResult* r) {
  const RenderOutput p1 = render_case(run, c, 1, candidate_seed(seed, 0), case_dir + "/part1", false);
  r->seconds += p1.seconds;
  for (const std::string& t : p1.todo)
    if (std::find(r->todo.begin(), r->todo.end(), t) == r->todo.end()) r->todo.push_back(t);
  return check_speedup(p1, r->render_seconds, r->tests_per_ray, bounds, c.points, &r->part1_seconds, &r->speedup);
}

}  // namespace

CaseResult grade_case(const RunSettings& run, const std::string& reference_root, const Case& c, uint64_t seed,
                      const std::string& case_dir, const Rules& rules) {
  CaseResult r;
  r.c = c;
  r.max_score = c.points;
  r.dir = case_dir;
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
    r.command = join_command(render_plan(c, false, rules), seed);
    return r;
  }
  const RenderPlan plan = render_plan(c, ref.deterministic, rules);
  r.command = join_command(plan, seed);
  const Renders rs = render_candidate(run, plan, seed, case_dir, &r);
  record_figures(rs, plan.share, ref, &r);
  if (!rs.ok()) {
    const std::string kind = failure_kind(rs.outs.back());
    r.signature[kind] = 1;
    // "1234 pixels are NaN or infinite ...": how many.
    if (kind == "failure_nan") r.signature["nan_pixels"] = std::atof(rs.outs.back().failure.c_str());
    return fail(rs.outs.back().failure);
  }
  const ImageBuffer& first = rs.radiance.images[0];
  if (first.width != ref.mean.width || first.height != ref.mean.height)
    return fail("the reference is " + std::to_string(ref.mean.width) + " x " + std::to_string(ref.mean.height) +
                ": remake it");

  std::vector<Check> checks;
  const ImageScore img = score_renders(rs.radiance, ref.mean, ref.variance, ref.runs, case_score_options(c, ref, rules));
  r.relmse = img.relmse;
  r.noise_ratio = img.noise_ratio;
  r.tail_ratio = img.tail_ratio;
  if (!img.deterministic) r.relmse_noise = img.relmse_expected;
  const ImageBuffer candidate = mean_of(rs.radiance.images);
  r.signature = image_signature(candidate, ref.mean, img);
  save_pictures(case_dir, candidate, ref, img);
  checks.push_back(check_image(img, c.points));
  // Noise is its own check, where the image is right: a wrong image's
  // problem is the image.
  if (img.passed) checks.push_back(check_noise(img, rules.noise_bound_for(c), rules.tail_bound, rules.noise_credit,
                                              case_method(c), c.points));

  if (c.kind == CaseKind::Rate) checks.push_back(rate_check(c, ref, rs, rules, &r.signature));
  if (c.part >= 2) {
    checks.push_back(cost_check(c, rs, rules, &r));
    add_cost_signature(r, &r.signature);
  }
  if (c.kind == CaseKind::Speedup) checks.push_back(speedup_check(run, c, seed, case_dir, rules.costs, &r));
  if (c.kind == CaseKind::Probability)
    checks.push_back(check_probability_image(case_dir + "/render/" + kProbabilityImageFile,
                                             reference_root + "/" + c.name + "/" + kProbabilityImageFile, c.points));

  for (const Check& k : checks) {
    r.metric += k.metric;
    if (!k.problems.empty()) r.signature["failed_" + k.name] = 1;
  }
  decide(checks, &r);
  return r;
}

}  // namespace grader
