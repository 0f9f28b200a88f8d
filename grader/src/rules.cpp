#include "grader/src/rules.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "grader/src/run_case.h"

namespace grader {

namespace fs = std::filesystem;

std::map<std::string, QueryCosts> read_plain_bvh_costs(const std::string& path) {
  std::map<std::string, QueryCosts> out;
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return out;
  Json j;
  try {
    j = pt::read_json_file(path);
  } catch (const std::exception& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
  const Json* cases = j.get("cases");
  if (!cases || cases->type != Json::Type::Object) throw std::runtime_error(path + ": no \"cases\" object");
  for (const auto& [name, v] : cases->members) {
    if (v.type != Json::Type::Object) throw std::runtime_error(path + ": case " + name + " is not an object");
    QueryCosts q;
    q.closest_tests = v.num("closest_tests_per_query", -1);
    q.shadow_tests = v.num("shadow_tests_per_query", -1);
    out[name] = q;
  }
  return out;
}

namespace {

// How many Monte Carlo images the cases score (a rate case scores two).
int scored_images(const std::vector<Case>& cases, const std::string& references) {
  int scored = 0;
  for (const Case& c : cases) {
    Reference ref;
    std::string why;
    const bool deterministic = load_reference(references, c, &ref, &why) && ref.deterministic;
    if (!deterministic) scored += c.kind == CaseKind::Rate ? 2 : 1;
  }
  return scored;
}

}  // namespace

Rules make_rules(const std::vector<Case>& all, const std::string& references) {
  return make_rules(all, references, {}, "");
}

Rules make_rules(const std::vector<Case>& all, const std::string& references, const std::vector<Case>& hidden,
                 const std::string& hidden_references) {
  Rules r;
  r.scored_images = std::max(1, scored_images(all, references) + scored_images(hidden, hidden_references));
  r.plain_bvh = read_plain_bvh_costs(references + "/plain_bvh_costs.json");
  if (!hidden_references.empty())
    for (const auto& [name, costs] : read_plain_bvh_costs(hidden_references + "/plain_bvh_costs.json"))
      r.plain_bvh[name] = costs;
  return r;
}

double Rules::noise_bound_for(const Case& c) const {
  const auto o = std::find(c.options.begin(), c.options.end(), "-o");
  const bool last_bounce_only = o != c.options.end() && o + 1 != c.options.end() && *(o + 1) == "0";
  const int bounces = std::min(case_int_option(c, "-m", 1), 16);
  if (!last_bounce_only || bounces < 2) return noise_bound;
  return noise_bound * std::pow(noise_growth_per_bounce, bounces - 1);
}

std::string case_method(const Case& c) {
  const int spp = case_int_option(c, "-s", 1), lights = case_int_option(c, "-l", 1);
  const bool hemisphere = std::find(c.options.begin(), c.options.end(), "-H") != c.options.end();
  switch (c.part) {
    case 1:
      return "jittered pixel sampling at -s " + std::to_string(spp);
    case 3:
      return hemisphere ? std::string("uniform hemisphere sampling (-H)")
                        : "light sampling (-l " + std::to_string(lights) + ")";
    case 4:
      return std::string("path tracing with light sampling at every bounce") +
             (hemisphere ? " (-H)" : "");
    case 5:
      return "adaptive sampling with light sampling";
    case 6:
      return "path tracing through mirror and glass (one direction per delta bounce)";
    case 7:
      return "importance sampling of the microfacet BRDF's normal distribution";
    case 8:
      return "importance sampling of the environment map";
    default:
      return "the thin lens sampled uniformly over its disk";
  }
}

RenderPlan render_plan(const Case& c, bool deterministic, const Rules& rules) {
  RenderPlan p;
  p.c = c;
  if (deterministic || rules.renders < 2) return p;
  p.renders = rules.renders;
  const int spp = case_int_option(c, "-s", 1);
  // Adaptive sampling's -s is the rule's maximum, not a budget to share.
  if (c.kind == CaseKind::Rate || spp % rules.renders != 0 || spp / rules.renders < 2) return p;
  // From part 5 on every render samples adaptively, and a pixel that may
  // stop after a batch is a different estimator at another -s: it stops
  // most often before a rare bright path came (light seen through glass),
  // so its expectation depends on -s. Split, the renders could not stop
  // at all. Only where the whole -s is one batch or less (no pixel stops
  // early either way) do the renders share it.
  if (c.part >= 5 && case_int_option(c, "-a", kDefaultAdaptiveBatch) < spp) return p;
  for (size_t i = 0; i + 1 < p.c.options.size(); ++i)
    if (p.c.options[i] == "-s") p.c.options[i + 1] = std::to_string(spp / rules.renders);
  p.share = 1.0 / rules.renders;
  return p;
}

uint64_t candidate_seed(uint64_t seed, int k) { return (uint64_t(1) << 32) + 64 * seed + uint64_t(k); }

}  // namespace grader
