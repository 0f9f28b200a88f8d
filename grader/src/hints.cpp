#include "grader/src/hints.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <fstream>
#include <set>
#include <stdexcept>

#include "grader/src/text.h"

namespace grader {

namespace {

// How two failing cases differ, from 0 (alike) to 1. A case one fails and
// the other passes counts 1: which cases fail is most of a signature (it
// says which part, and which scenes: meshes, spheres, open skies, -H). Of
// two failing cases, half is how the image's mean moved (its direction
// and size, compared as tanh of twice the log ratio, so that x1.3 and x2
// are both "too bright", apart from x0.7), a third is where it moved (each
// region's log ratio against the whole image's), and the rest is what
// failed: the image, the noise, the rate, the costs, or the render itself.

double figure(const CaseSignature& c, const char* key, double fallback) {
  const auto it = c.figures.find(key);
  return it == c.figures.end() ? fallback : it->second;
}

double log_ratio(const CaseSignature& c, const char* key) {
  const double r = figure(c, key, 1.0);
  return r > 0 ? std::clamp(std::log(r), -3.0, 3.0) : -3.0;
}

// What failed in a case: a bit per check and per kind of broken render.
unsigned failure_bits(const CaseSignature& c) {
  static const char* const kKinds[] = {"failed_image", "failed_noise", "failed_rate", "failed_cost",
                                       "failed_speedup", "failure_nan", "failure_negative", "failure_crash",
                                       "failure_timeout", "failure_exit", "failure_todo", "failure_output"};
  unsigned bits = 0;
  for (unsigned i = 0; i < sizeof kKinds / sizeof kKinds[0]; ++i)
    if (figure(c, kKinds[i], 0) > 0) bits |= 1u << i;
  return bits;
}

double case_distance(const CaseSignature* a, const CaseSignature* b) {
  const bool fa = a && a->failed, fb = b && b->failed;
  if (fa != fb) return 1.0;
  if (!fa) return 0.0;
  const double mean = std::fabs(std::tanh(2 * log_ratio(*a, "mean_ratio")) - std::tanh(2 * log_ratio(*b, "mean_ratio")));
  static const char* const kRegions[] = {"ratio_bright", "ratio_dark",  "ratio_mid",   "ratio_edges",
                                         "ratio_flat",   "ratio_top",   "ratio_bottom", "rate_ratio",
                                         "shadow_rays_ratio", "shadow_tests_ratio", "closest_tests_ratio"};
  // How differently the two moved a region, relative to their whole image.
  const auto moved = [&](const char* key) {
    return std::fabs((log_ratio(*a, key) - log_ratio(*a, "mean_ratio")) -
                     (log_ratio(*b, key) - log_ratio(*b, "mean_ratio")));
  };
  double where = 0;
  for (const char* key : kRegions) where += moved(key);
  // The grid's cells are regions too: where in the picture it moved (a
  // catalogue made before the grid has none, and they count for nothing).
  for (int r = 0; r < kGridSide; ++r)
    for (int col = 0; col < kGridSide; ++col) {
      const std::string key = grid_key(r, col);
      if (a->figures.count(key) && b->figures.count(key)) where += moved(key.c_str());
    }
  where = std::min(1.0, where / 2.0);
  const unsigned x = failure_bits(*a) ^ failure_bits(*b);
  const double what = x == 0 ? 0.0 : 1.0;
  return 0.5 * std::min(1.0, mean) + 0.3 * where + 0.2 * what;
}

// The median of the build's figure `key` over the cases `bug` fails.
double median_over(const BuildSignature& build, const KnownBug& bug, const char* key) {
  std::vector<double> v;
  for (const auto& [name, c] : bug.cases) {
    if (!c.failed) continue;
    const auto b = build.find(name);
    if (b == build.end()) continue;
    const auto f = b->second.figures.find(key);
    if (f != b->second.figures.end()) v.push_back(f->second);
  }
  if (v.empty()) return -1;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

std::string factor(double x) {
  if (x < 0) return "an unknown factor";
  if (x >= 10) return fmt("x%.0f", x);
  if (x < 0.1) return fmt("x%.1g", x);
  // Near 1, enough digits to show which way it moved (x0.9997, not x1).
  const std::string two = fmt("x%.2g", x);
  return two == "x1" && x != 1 ? fmt("x%.4g", x) : two;
}

// Swaps every `a` in `s` with `b` and every `b` with `a`.
void swap_words(std::string* s, const std::string& a, const std::string& b) {
  std::string out;
  for (size_t i = 0; i < s->size();) {
    if (s->compare(i, a.size(), a) == 0) {
      out += b, i += a.size();
    } else if (s->compare(i, b.size(), b) == 0) {
      out += a, i += b.size();
    } else {
      out += (*s)[i++];
    }
  }
  *s = out;
}

// The bug's words with the build's figures put in. Words that say the
// image is too bright (or too dark) are made to agree with the build's own
// image ratio, the {ratio} figure: a bug's words describe the bug as the
// catalogue saw it, and a build whose image moved the other way would read
// "too bright (image x0.99)".
std::string fill(const BuildSignature& build, const KnownBug& bug) {
  std::string s = bug.hint;
  const double ratio = median_over(build, bug, "mean_ratio");
  const size_t bright = s.find("too bright"), dark = s.find("too dark");
  const bool says_bright = bright != std::string::npos && (dark == std::string::npos || bright < dark);
  const bool says_dark = dark != std::string::npos && !says_bright;
  if (ratio > 0 && ((says_bright && ratio < 1) || (says_dark && ratio > 1))) {
    swap_words(&s, "too bright", "too dark");
    swap_words(&s, "brighter", "darker");
  }
  const std::pair<const char*, const char*> slots[] = {{"{ratio}", "mean_ratio"},
                                                       {"{rate}", "rate_ratio"},
                                                       {"{tests}", "closest_tests_ratio"},
                                                       {"{shadow_tests}", "shadow_tests_ratio"},
                                                       {"{shadow_rays}", "shadow_rays_ratio"},
                                                       {"{noise}", "noise_ratio"}};
  for (const auto& [slot, key] : slots)
    for (size_t at; (at = s.find(slot)) != std::string::npos;)
      s.replace(at, std::string(slot).size(), factor(median_over(build, bug, key)));
  return s;
}

// The build's failing cases that the bug fails too, in the case list's
// order when the groups know it (else by name).
std::vector<std::string> explained_cases(const BuildSignature& build, const KnownBug& bug) {
  std::vector<std::string> out;
  for (const auto& [name, c] : build) {
    if (!c.failed) continue;
    const auto b = bug.cases.find(name);
    if (b != bug.cases.end() && b->second.failed) out.push_back(name);
  }
  return out;
}

// "; explains p6_m2, p6_m3 (2 of 5 failing cases)", at most six names.
std::string cases_clause(const std::vector<std::string>& cases, const BuildSignature& build) {
  const size_t failing =
      size_t(std::count_if(build.begin(), build.end(), [](const auto& c) { return c.second.failed; }));
  if (cases.empty()) return "; explains none of the failing cases";
  std::string s = "; explains ";
  for (size_t i = 0; i < cases.size() && i < 6; ++i) s += (i ? ", " : "") + cases[i];
  if (cases.size() > 6) s += ", ...";
  return s + " (" + std::to_string(cases.size()) + " of " + std::to_string(failing) + " failing case" +
         (failing == 1 ? "" : "s") + ")";
}

std::string section_of(const std::string& readme) {
  const auto [file, section] = readme_section(readme);
  return section.empty() ? file : file + " (\"" + section + "\")";
}

BuildSignature cases_from_json(const Json& j, const std::string& where) {
  BuildSignature out;
  if (j.type != Json::Type::Object) throw std::runtime_error(where + ": \"cases\" is not an object");
  for (const auto& [name, c] : j.members) {
    CaseSignature cs;
    cs.failed = c.flag("failed");
    if (const Json* f = c.get("signature"))
      for (const auto& [key, v] : f->members)
        if (v.type == Json::Type::Number) cs.figures[key] = v.number;
    out[name] = cs;
  }
  return out;
}

}  // namespace

Catalogue read_catalogue(const std::string& path) {
  const Json j = pt::read_json_file(path);
  Catalogue cat;
  cat.commit = j.str("commit");
  cat.date = j.str("date");
  const Json* bugs = j.get("bugs");
  if (!bugs || bugs->type != Json::Type::Array) throw std::runtime_error(path + ": no \"bugs\" array");
  for (const Json& b : bugs->array) {
    KnownBug k;
    k.name = b.str("name");
    k.part = int(b.num("part", 0));
    k.function = b.str("function");
    k.file = b.str("file");
    k.readme = b.str("readme");
    k.hint = b.str("hint");
    if (k.name.empty() || k.function.empty() || k.hint.empty())
      throw std::runtime_error(path + ": a bug without a name, function or hint");
    const Json* cases = b.get("cases");
    if (!cases) throw std::runtime_error(path + ": bug " + k.name + " has no cases");
    k.cases = cases_from_json(*cases, path + ": bug " + k.name);
    if (const Json* pd = b.get("probes_disagree"); pd && pd->type == Json::Type::Array) {
      k.has_probes = true;
      for (const Json& f : pd->array)
        if (f.type == Json::Type::String) k.probes_disagree.push_back(f.string);
    }
    cat.bugs.push_back(std::move(k));
  }
  if (const Json* pf = j.get("probed_functions"); pf && pf->type == Json::Type::Array)
    for (const Json& f : pf->array)
      if (!f.str("function").empty()) cat.probed_functions.emplace_back(f.str("function"), int(f.num("part", 0)));
  cat.solved_parts = read_solved_parts(solved_parts_path(path));
  return cat;
}

std::string solved_parts_path(const std::string& catalogue_path) {
  namespace fs = std::filesystem;
  const fs::path grader_dir = fs::absolute(catalogue_path).parent_path();
  return (grader_dir.parent_path() / "solved_parts.txt").string();
}

std::set<int> read_solved_parts(const std::string& path) {
  std::set<int> parts;
  std::ifstream in(path);
  if (!in) return parts;  // no file: every part is the students'
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const size_t b = line.find_first_not_of(" \t\r"), e = line.find_last_not_of(" \t\r");
    if (b == std::string::npos || line[b] == '#') continue;
    const std::string v = line.substr(b, e - b + 1);
    if (v.size() != 1 || v[0] < '1' || v[0] > '9')
      throw std::runtime_error(path + ":" + std::to_string(number) + ": '" + v +
                               "' is not a part number (one of 1-9 a line, or a # comment)");
    parts.insert(v[0] - '0');
  }
  return parts;
}

BuildSignature build_signature(const std::vector<CaseResult>& results) {
  BuildSignature b;
  for (const CaseResult& r : results) {
    CaseSignature c;
    // A case stopped at a TODO line is a part not written yet, not a bug:
    // it counts as neither failing nor passing.
    const auto todo = r.signature.find("failure_todo");
    if (todo != r.signature.end() && todo->second > 0) continue;
    c.failed = r.verdict != Verdict::Passed || r.score < r.max_score;
    c.figures = r.signature;
    b[r.c.name] = c;
  }
  return b;
}

CaseGroups case_groups(const std::vector<Case>& cases) {
  CaseGroups g;
  const auto has = [](const Case& c, const char* opt) {
    return std::find(c.options.begin(), c.options.end(), opt) != c.options.end();
  };
  const auto scene = [](const Case& c, const char* part) { return c.scene.find(part) != std::string::npos; };
  for (const Case& c : cases) {
    std::vector<std::string>& v = g[c.name];
    v.push_back("part" + std::to_string(c.part));
    if (c.part >= 3) v.push_back(has(c, "-H") ? "hemisphere" : "light_sampling");
    if (has(c, "-e") || scene(c, "ambient")) v.push_back("open_sky");
    if (scene(c, "sphere")) v.push_back("spheres");
    for (const char* mesh : {"bunny", "cow", "dragon", "teapot", "armadillo"})
      if (scene(c, mesh)) v.push_back("mesh");
    if (scene(c, "CBempty") || scene(c, "CBlights") || (scene(c, "cow") && !has(c, "-e") && c.part >= 3))
      v.push_back("delta_lights");
    if (has(c, "-o")) v.push_back("last_bounce_only");
    // Project 3-2's materials, lights and camera.
    if (c.scene == "CBspheres.dae") v.push_back("mirror_glass");
    if (scene(c, "microfacet")) v.push_back("microfacet");
    if (has(c, "-e")) v.push_back("environment");
    const auto b = std::find(c.options.begin(), c.options.end(), "-b");
    if (b != c.options.end() && b + 1 != c.options.end() && std::atof((b + 1)->c_str()) > 0)
      v.push_back("depth_of_field");
    if (c.kind == CaseKind::Rate) v.push_back("adaptive");
    if (c.kind == CaseKind::Speedup) v.push_back("speedup");
  }
  return g;
}

double signature_distance(const BuildSignature& build, const BuildSignature& bug, const CaseGroups& groups) {
  std::set<std::string> names;
  for (const auto& [n, c] : build)
    if (c.failed) names.insert(n);
  for (const auto& [n, c] : bug)
    if (c.failed) names.insert(n);
  if (names.empty()) return 0;
  double sum = 0;
  for (const std::string& n : names) {
    const auto a = build.find(n), b = bug.find(n);
    sum += case_distance(a == build.end() ? nullptr : &a->second, b == bug.end() ? nullptr : &b->second);
  }
  // The fraction of each group's cases that fail, for both.
  std::map<std::string, std::pair<double, double>> fraction;  // group -> (build, bug)
  std::map<std::string, int> size;
  const auto fails = [](const BuildSignature& s, const std::string& n) {
    const auto it = s.find(n);
    return it != s.end() && it->second.failed;
  };
  for (const auto& [n, gs] : groups)
    for (const std::string& gname : gs) {
      ++size[gname];
      fraction[gname].first += fails(build, n);
      fraction[gname].second += fails(bug, n);
    }
  double group_sum = 0;
  int group_count = 0;
  for (const auto& [gname, f] : fraction) {
    if (f.first == 0 && f.second == 0) continue;
    group_sum += std::fabs(f.first - f.second) / size[gname];
    ++group_count;
  }
  const double by_case = sum / double(names.size()), by_group = group_count ? group_sum / group_count : 0.0;
  return 0.5 * by_case + 0.5 * by_group;
}

namespace {

// From candidates sorted nearest first: up to max_hints within
// kHintDistance, and beyond the nearest only bugs nearly as near (a second
// guess far behind a close first one is noise, not help), one per function.
std::vector<Hint> select_hints(std::vector<Hint> all, const BuildSignature& build, int max_hints) {
  std::stable_sort(all.begin(), all.end(), [](const Hint& a, const Hint& b) { return a.rank < b.rank; });
  std::vector<Hint> out;
  std::set<std::string> functions;
  for (Hint& h : all) {
    if (int(out.size()) >= max_hints) break;
    // In rank order a farther bug may come before a nearer one: skip it, not stop.
    if (h.distance > kHintDistance || (!out.empty() && h.distance > out[0].distance + kHintSpread)) continue;
    if (!functions.insert(h.bug->function).second) continue;
    h.words = fill(build, *h.bug);
    h.cases = explained_cases(build, *h.bug);
    h.text = h.words + " (" + h.bug->function + " in " + h.bug->file + "; read " + section_of(h.bug->readme) +
             cases_clause(h.cases, build) + ")";
    out.push_back(h);
  }
  return out;
}

// The part whose stage folder holds the bug's function (stages/partN_...),
// else the bug's own part (common/bsdf.h's diffuse_f is part 3's).
int function_part(const KnownBug& bug) {
  const std::string prefix = "stages/part";
  if (bug.file.rfind(prefix, 0) == 0 && bug.file.size() > prefix.size() &&
      std::isdigit(static_cast<unsigned char>(bug.file[prefix.size()])))
    return bug.file[prefix.size()] - '0';
  return bug.part;
}

// The functions of the parts the tree gives solved: the functions whose
// stage folder is of a solved part, and those of the bugs of a solved part
// (a function of a part may hold another part's bug, as generate_ray, of
// part 1, holds camera_not_normalized, of part 3).
std::set<std::string> solved_functions(const Catalogue& catalogue) {
  std::set<std::string> out;
  for (const KnownBug& bug : catalogue.bugs)
    if (catalogue.solved_parts.count(function_part(bug)) ||
        (catalogue.solved_parts.count(bug.part) && function_part(bug) == bug.part))
      out.insert(bug.function);
  return out;
}

bool names_solved_code(const KnownBug& bug, const Catalogue& catalogue, const std::set<std::string>& functions) {
  return catalogue.solved_parts.count(bug.part) > 0 || functions.count(bug.function) > 0;
}

}  // namespace

int earliest_failing_part(const BuildSignature& build, const CaseGroups& groups) {
  int earliest = 0;
  for (const auto& [name, c] : build) {
    if (!c.failed) continue;
    const auto g = groups.find(name);
    if (g == groups.end()) continue;
    for (const std::string& group : g->second)
      if (group.rfind("part", 0) == 0) {
        const int part = std::atoi(group.c_str() + 4);
        if (part > 0 && (earliest == 0 || part < earliest)) earliest = part;
      }
  }
  return earliest;
}

std::vector<Hint> likely_bugs(const BuildSignature& build, const Catalogue& catalogue, const CaseGroups& groups,
                              int max_hints, const std::string& exclude, const ProbeVerdicts* probes) {
  return likely_bugs_without(build, catalogue, groups, [&](const KnownBug& b) { return b.name == exclude; },
                             max_hints, probes);
}

namespace {

// Which functions' answers the checks of a function also depend on: its
// callees among the functions students write. A function whose callee's
// checks disagree too is named after that callee (its own checks may
// disagree only through it).
const std::map<std::string, std::vector<std::string>>& callees() {
  static const std::map<std::string, std::vector<std::string>> m = {
      {"camera_sample_ray", {"generate_ray"}},
      {"raytrace_pixel", {"camera_sample_ray", "generate_ray"}},
      {"raytrace_pixel_adaptive", {"pixel_converged", "camera_sample_ray", "generate_ray"}},
      {"BVH::intersect", {"BVH::build", "slab_test", "intersect_triangle", "intersect_sphere"}},
      {"BVH::occluded", {"BVH::build", "slab_test", "intersect_triangle", "intersect_sphere"}},
      {"BVH::build", {"slab_test"}},
      {"mirror_sample_f", {"reflect"}},
      {"refraction_sample_f", {"refract"}},
      {"glass_sample_f", {"refract", "reflect", "schlick_reflectance"}},
      {"microfacet_f", {"microfacet_D", "microfacet_F"}},
      {"microfacet_pdf", {"microfacet_D"}},
      {"microfacet_sample_f", {"microfacet_f", "microfacet_D", "microfacet_F"}},
      {"sample_environment", {"build_environment_distribution", "environment_pdf"}},
      // The light estimators' checks trace their scene with the given
      // brute-force intersector, which calls part 1's tests.
      {"zero_bounce_radiance", {"intersect_triangle", "intersect_sphere"}},
      {"estimate_direct_lighting_hemisphere", {"diffuse_f", "intersect_triangle", "intersect_sphere"}},
      {"estimate_direct_lighting_importance", {"diffuse_f", "intersect_triangle", "intersect_sphere"}},
      {"at_least_one_bounce_radiance",
       {"zero_bounce_radiance", "estimate_direct_lighting_hemisphere", "estimate_direct_lighting_importance",
        "diffuse_f", "intersect_triangle", "intersect_sphere"}},
      {"environment_pdf", {"build_environment_distribution"}},
  };
  return m;
}

// The part of each failing case, from its groups ("partN").
std::vector<std::pair<std::string, int>> failing_parts(const BuildSignature& build, const CaseGroups& groups) {
  std::vector<std::pair<std::string, int>> out;
  for (const auto& [name, c] : build) {
    if (!c.failed) continue;
    int part = 0;
    if (const auto g = groups.find(name); g != groups.end())
      for (const std::string& group : g->second)
        if (group.rfind("part", 0) == 0) part = std::atoi(group.c_str() + 4);
    out.emplace_back(name, part);
  }
  return out;
}

// The hints from the function checks: each function that answers them
// differently, of a part that is the students' and that some failing case
// runs (a case of part k runs parts 1 to k), callees first, then by part.
std::vector<Hint> probe_hints(const BuildSignature& build, const Catalogue& catalogue, const CaseGroups& groups,
                              const ProbeVerdicts& probes, const std::set<std::string>& solved, int max_hints,
                              const std::function<bool(const KnownBug&)>& left_out) {
  const auto failing = failing_parts(build, groups);
  int latest = 0;
  for (const auto& [name, part] : failing) latest = std::max(latest, part);
  std::vector<const ProbeVerdict*> wrong;
  for (const auto& [function, v] : probes)
    if (!v.agrees && v.part >= 1 && v.part <= latest && !catalogue.solved_parts.count(v.part) && !solved.count(function))
      wrong.push_back(&v);
  // How many of a function's callees, and theirs, disagree too: a function
  // comes after those it calls (raytrace_pixel after camera_sample_ray
  // after generate_ray).
  const auto wrong_callees = [&](const ProbeVerdict* v) {
    std::set<std::string> seen;
    std::vector<std::string> todo = {v->function};
    while (!todo.empty()) {
      const std::string f = todo.back();
      todo.pop_back();
      const auto c = callees().find(f);
      if (c == callees().end()) continue;
      for (const std::string& g : c->second)
        if (seen.insert(g).second) todo.push_back(g);
    }
    return int(std::count_if(seen.begin(), seen.end(), [&](const std::string& f) {
      const auto it = probes.find(f);
      return it != probes.end() && !it->second.agrees;
    }));
  };
  // Of two functions whose checks disagree and neither calls the other, the
  // one with a known bug nearer the build's signature first.
  std::map<std::string, double> nearest;
  for (const KnownBug& bug : catalogue.bugs) {
    if (left_out(bug)) continue;
    const double d = signature_distance(build, bug.cases, groups);
    const auto it = nearest.find(bug.function);
    if (it == nearest.end() || d < it->second) nearest[bug.function] = d;
  }
  const auto near = [&](const ProbeVerdict* v) {
    const auto it = nearest.find(v->function);
    return it == nearest.end() ? 1.0 : it->second;
  };
  std::stable_sort(wrong.begin(), wrong.end(), [&](const ProbeVerdict* a, const ProbeVerdict* b) {
    const int da = wrong_callees(a), db = wrong_callees(b);
    if (da != db) return da < db;
    if (near(a) != near(b)) return near(a) < near(b);
    return a->part < b->part;
  });
  std::vector<Hint> out;
  for (const ProbeVerdict* v : wrong) {
    if (int(out.size()) >= max_hints) break;
    auto stand_in = std::make_shared<KnownBug>();
    stand_in->name = "checks of " + v->function;
    stand_in->function = v->function;
    stand_in->part = v->part;
    // Where the function is: as a known bug of it says, else where the
    // known bugs of its part's stage folder are (one file per stage, but
    // for part 1's).
    for (const KnownBug& bug : catalogue.bugs)
      if (bug.function == v->function && !bug.file.empty()) {
        stand_in->file = bug.file, stand_in->readme = bug.readme;
        break;
      }
    const std::string folder = "stages/part" + std::to_string(v->part) + "_";
    for (const KnownBug& bug : catalogue.bugs)
      if (stand_in->file.empty() && bug.file.rfind(folder, 0) == 0 && v->part != 1)
        stand_in->file = bug.file, stand_in->readme = bug.readme;
    if (stand_in->file.empty()) stand_in->file = stand_in->readme = "part " + std::to_string(v->part) + "'s stage folder";
    Hint h;
    h.from_probe = true;
    h.checked = stand_in;
    h.bug = stand_in.get();
    h.words = v->function + " answers the grader's function checks differently from the reference's (" + v->detail + ")";
    for (const auto& [name, part] : failing)
      if (part >= v->part) h.cases.push_back(name);
    h.text = h.words + " (" + v->function + " in " + stand_in->file + "; read " + section_of(stand_in->readme) +
             cases_clause(h.cases, build) + ")";
    out.push_back(h);
  }
  return out;
}

}  // namespace

ProbeVerdicts catalogued_probes(const KnownBug& bug, const Catalogue& catalogue) {
  ProbeVerdicts out;
  if (!bug.has_probes) return out;
  for (const auto& [function, part] : catalogue.probed_functions) {
    ProbeVerdict v;
    v.function = function;
    v.part = part;
    v.agrees = std::find(bug.probes_disagree.begin(), bug.probes_disagree.end(), function) == bug.probes_disagree.end();
    if (!v.agrees) v.detail = "as catalogued";
    out[function] = v;
  }
  return out;
}

namespace {

// The signatures' bugs (likely_bugs_without without the function checks'
// own hints); `probes` only moves the bugs of functions whose checks agree
// down.
std::vector<Hint> signature_hints(const BuildSignature& build, const Catalogue& catalogue, const CaseGroups& groups,
                                  const std::function<bool(const KnownBug&)>& left_out, int max_hints,
                                  const ProbeVerdicts* probes) {
  if (max_hints <= 0) return {};
  // A case of part k runs stages 1..k only (--part k): a bug in a later
  // part cannot have failed it. Such bugs are named only when no bug that
  // could have is near (a case can fail by chance).
  const int earliest = earliest_failing_part(build, groups);
  const std::set<std::string> solved = solved_functions(catalogue);
  std::vector<Hint> possible, later;
  for (const KnownBug& bug : catalogue.bugs) {
    if (left_out(bug) || names_solved_code(bug, catalogue, solved)) continue;
    Hint h{&bug, signature_distance(build, bug.cases, groups), 0.0, "", "", {}, false, nullptr};
    // A bug of an earlier part usually fails that part's cases too: of two
    // bugs about as near, the one of the earliest failing case's part is
    // the likelier.
    h.rank = h.distance - (earliest > 0 && bug.part == earliest ? kOwnPartBonus : 0.0);
    // A function whose checks agree is less likely to hold the bug.
    if (probes) {
      const auto v = probes->find(bug.function);
      if (v != probes->end() && v->second.agrees) h.rank += kProbeAgreePenalty;
    }
    (earliest > 0 && bug.part > earliest ? later : possible).push_back(h);
  }
  std::vector<Hint> hints = select_hints(possible, build, max_hints);
  if (hints.empty()) return select_hints(std::move(later), build, max_hints);
  // A bug of an earlier part usually fails that part's cases too: a build
  // whose earliest failing case is of part k most often has its bug in part
  // k. When no hint is of part k, the nearest bug of part k joins them (in
  // the last place when they are full), if it is nearly as near as the first.
  if (earliest > 0 &&
      std::none_of(hints.begin(), hints.end(), [&](const Hint& h) { return h.bug->part == earliest; })) {
    std::vector<Hint> own;
    for (const Hint& h : possible) {
      // Not a function whose checks agree: they say it is not there.
      const bool cleared = probes && probes->count(h.bug->function) && probes->at(h.bug->function).agrees;
      if (h.bug->part == earliest && !cleared) own.push_back(h);
    }
    std::vector<Hint> best_own = select_hints(std::move(own), build, 1);
    if (!best_own.empty() && best_own.front().distance <= hints.front().distance + kHintSpread) {
      if (int(hints.size()) == max_hints) hints.pop_back();
      hints.push_back(best_own.front());
    }
  }
  return hints;
}

}  // namespace

std::vector<Hint> likely_bugs_without(const BuildSignature& build, const Catalogue& catalogue,
                                      const CaseGroups& groups, const std::function<bool(const KnownBug&)>& left_out,
                                      int max_hints, const ProbeVerdicts* probes) {
  const bool fails = std::any_of(build.begin(), build.end(), [](const auto& c) { return c.second.failed; });
  if (!fails) return {};
  if (probes && !probes->empty()) {
    const std::set<std::string> solved = solved_functions(catalogue);
    std::vector<Hint> first = probe_hints(build, catalogue, groups, *probes, solved, max_hints, left_out);
    std::set<std::string> named;
    for (const Hint& h : first) named.insert(h.bug->function);
    if (int(first.size()) >= max_hints) return first;
    // Then the signatures' bugs, of the functions not named yet; those
    // whose checks agree farther down.
    std::vector<Hint> ranked = signature_hints(build, catalogue, groups,
                                               [&](const KnownBug& b) { return left_out(b) || named.count(b.function) > 0; },
                                               max_hints - int(first.size()), probes);
    for (Hint& h : ranked) first.push_back(std::move(h));
    return first;
  }
  return signature_hints(build, catalogue, groups, left_out, max_hints, nullptr);
}

// One case: only the bugs that fail it are candidates, and the distance is
// the case's own (the whole-run distance would halve it: with one failing
// case, every candidate matches the pattern of failing cases exactly).
std::vector<Hint> likely_bugs_for_case(const std::string& case_name, const CaseSignature& figures,
                                       const Catalogue& catalogue, const CaseGroups& groups, int max_hints) {
  (void)groups;
  if (!figures.failed) return {};
  const BuildSignature build = {{case_name, figures}};
  const std::set<std::string> solved = solved_functions(catalogue);
  std::vector<Hint> all;
  for (const KnownBug& bug : catalogue.bugs) {
    const auto it = bug.cases.find(case_name);
    if (it == bug.cases.end() || !it->second.failed) continue;
    if (names_solved_code(bug, catalogue, solved)) continue;
    const double d = case_distance(&figures, &it->second);
    all.push_back(Hint{&bug, d, d, "", "", {}, false, nullptr});
  }
  return select_hints(std::move(all), build, max_hints);
}

const char* const kNoHintClose =
    "Likely cause: no known bug's signature is close to this one; the grader's own messages and figures are what "
    "there is to go on";

std::vector<std::string> hint_lines(const std::vector<Hint>& hints) {
  if (hints.empty()) return {kNoHintClose};
  std::vector<std::string> lines;
  for (size_t i = 0; i < hints.size(); ++i)
    lines.push_back("Likely cause " + std::to_string(i + 1) + " of " + std::to_string(hints.size()) + ": " +
                    hints[i].text);
  return lines;
}

std::vector<std::string> hint_lines(const std::vector<CaseResult>& results, const Catalogue& catalogue,
                                    const CaseGroups& groups, const ProbeVerdicts* probes) {
  const BuildSignature build = build_signature(results);
  const bool fails = std::any_of(build.begin(), build.end(), [](const auto& c) { return c.second.failed; });
  if (!fails || catalogue.bugs.empty()) return {};
  const std::vector<Hint> hints = likely_bugs(build, catalogue, groups, 3, "", probes);
  std::vector<std::string> lines = hint_lines(hints);
  if (!probes) return lines;
  // Then a line for each other function whose checks disagree and that a
  // hint may name: of the students' parts and of parts a failing case runs.
  std::set<std::string> named;
  for (const Hint& h : hints)
    if (h.from_probe) named.insert(h.bug->function);
  int latest = 0;
  for (const auto& [name, part] : failing_parts(build, groups)) latest = std::max(latest, part);
  const std::set<std::string> solved = solved_functions(catalogue);
  ProbeVerdicts shown;
  for (const auto& [function, v] : *probes)
    if (v.part >= 1 && v.part <= latest && !catalogue.solved_parts.count(v.part) && !solved.count(function) &&
        !named.count(function))
      shown[function] = v;
  for (const std::string& l : probe_lines(shown)) lines.push_back(l);
  return lines;
}

std::pair<std::string, std::string> readme_section(const std::string& readme) {
  const size_t hash = readme.find('#');
  if (hash == std::string::npos) return {readme, ""};
  return {readme.substr(0, hash), readme.substr(hash + 1)};
}

std::string held_out_table(const Catalogue& catalogue, const CaseGroups& groups, HoldOut hold_out,
                           HintRates* rates, bool use_probes) {
  std::string rows;
  HintRates r;
  struct Count {
    int n = 0, first = 0, top = 0, part = 0;
  } projects[2];  // 3-1 (parts 1-5), 3-2 (parts 6-9)
  for (const KnownBug& bug : catalogue.bugs) {
    const bool fails = std::any_of(bug.cases.begin(), bug.cases.end(), [](const auto& c) { return c.second.failed; });
    if (!fails) continue;
    const auto left_out = [&](const KnownBug& other) {
      return hold_out == HoldOut::Bug ? other.name == bug.name : other.function == bug.function;
    };
    const ProbeVerdicts probes = use_probes ? catalogued_probes(bug, catalogue) : ProbeVerdicts{};
    const std::vector<Hint> hints = likely_bugs_without(bug.cases, catalogue, groups, left_out, 3, &probes);
    const bool first = !hints.empty() && hints.front().bug->function == bug.function;
    bool function_ok = false, part_ok = false;
    std::string named;
    for (const Hint& h : hints) {
      function_ok |= h.bug->function == bug.function;
      part_ok |= h.bug->part == bug.part;
      named += (named.empty() ? "" : ", ") + h.bug->function + (h.from_probe ? std::string(" (checks)") : fmt(" (%.2f)", h.distance));
    }
    Count& c = projects[bug.part <= 5 ? 0 : 1];
    ++c.n, c.first += first, c.top += function_ok, c.part += part_ok;
    const auto yes = [](bool b) { return std::string(b ? "yes" : "no"); };
    rows += "| " + bug.name + " | " + std::to_string(bug.part) + " | " + bug.function + " | " +
            (named.empty() ? std::string("none close") : named) + " | " + yes(first) + " | " + yes(function_ok) +
            " | " + yes(part_ok) + " |\n";
  }
  const int n = projects[0].n + projects[1].n;
  r.bugs = n;
  if (n) {
    r.function_first = double(projects[0].first + projects[1].first) / n;
    r.function_top3 = double(projects[0].top + projects[1].top) / n;
    r.part_top3 = double(projects[0].part + projects[1].part) / n;
  }
  if (rates) *rates = r;
  const auto line = [](const char* what, const Count& c) {
    const auto pct = [&](int k) {
      return std::to_string(k) + " of " + std::to_string(c.n) + (c.n ? fmt(" (%.0f %%)", 100.0 * k / c.n) : "");
    };
    return std::string(what) + ": right function first " + pct(c.first) + ", among the first three " + pct(c.top) +
           "; right part among the first three " + pct(c.part) + ".\n";
  };
  return "| bug | part | function | hints (function, distance) | right function first | right function in the "
         "first three | right part in the first three |\n|---|---:|---|---|---|---|---|\n" +
         rows + "\n" + line("Project 3-1 (parts 1-5)", projects[0]) + line("Project 3-2 (parts 6-9)", projects[1]) +
         line("All", Count{n, projects[0].first + projects[1].first, projects[0].top + projects[1].top,
                             projects[0].part + projects[1].part});
}

std::vector<std::string> hint_lines_for_folder(const std::string& dir, const Catalogue& catalogue,
                                               const CaseGroups& groups, const std::string& references_dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_directory(fs::path(dir) / "cases", ec))
    throw std::runtime_error(dir + ": not a grader output folder (no cases/)");
  std::vector<CaseResult> results;
  for (const auto& entry : fs::directory_iterator(fs::path(dir) / "cases")) {
    const fs::path path = entry.path() / "result.json";
    if (!fs::exists(path, ec)) continue;
    CaseResult r;
    if (!case_result_from_json(pt::read_json_file(path.string()), &r))
      throw std::runtime_error(path.string() + ": not a case result");
    results.push_back(r);
  }
  const ProbeVerdicts probes = references_dir.empty() ? ProbeVerdicts{} : probe_verdicts_for_folder(dir, references_dir);
  return hint_lines(results, catalogue, groups, &probes);
}

}  // namespace grader
