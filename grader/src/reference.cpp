#include "grader/src/reference.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <map>
#include <mutex>
#include <thread>
#include <vector>

#include "common/clock.h"
#include "common/image_io.h"
#include "grader/src/probability_image.h"
#include "grader/src/rules.h"
#include "grader/src/text.h"

namespace grader {

namespace fs = std::filesystem;

bool load_reference(const std::string& root, const Case& c, Reference* ref, std::string* why) {
  const std::string dir = root + "/" + c.name;
  if (!fs::exists(dir + "/meta.json")) {
    *why = "no reference in " + dir + " (make it with: grader make-references --case " + c.name + ")";
    return false;
  }
  try {
    ref->meta = pt::read_json_file(dir + "/meta.json");
    if (ref->meta.str("digest") != case_digest(c)) {
      *why = "the reference in " + dir + " was made for another definition of the case (remake it)";
      return false;
    }
    ref->runs = int(ref->meta.num("runs", 0));
    ref->deterministic = ref->meta.flag("deterministic");
    ref->mean = pt::read_pfm(dir + "/mean.pfm");
    ref->variance = pt::read_pfm(dir + "/variance.pfm");
    if (c.kind == CaseKind::Probability && !fs::exists(dir + "/" + kProbabilityImageFile))
      throw std::runtime_error(dir + "/" + kProbabilityImageFile + " is missing");
    if (c.kind == CaseKind::Rate) {
      ref->rate_mean = pt::read_pfm(dir + "/rate_mean.pfm");
      ref->rate_variance = pt::read_pfm(dir + "/rate_variance.pfm");
    }
  } catch (const std::exception& e) {
    *why = std::string("broken reference: ") + e.what();
    return false;
  }
  return true;
}

namespace {

// Welford's running mean and M2 per pixel channel, in double precision.
struct Accumulator {
  int n = 0;
  int width = 0, height = 0;
  std::vector<double> mean, m2;  // three per pixel, in the image's order
  void add(const ImageBuffer& img) {
    if (n == 0) {
      width = img.width, height = img.height;
      mean.assign(img.pixels.size() * 3, 0.0);
      m2.assign(img.pixels.size() * 3, 0.0);
    }
    ++n;
    for (size_t i = 0; i < mean.size(); ++i) {
      const double v = img.pixels[i / 3][int(i % 3)];
      const double d = v - mean[i];
      mean[i] += d / n;
      m2[i] += d * (v - mean[i]);
    }
  }
  ImageBuffer mean_image() const {
    ImageBuffer img(width, height);
    for (size_t i = 0; i < mean.size(); ++i) img.pixels[i / 3][int(i % 3)] = float(mean[i]);
    return img;
  }
  ImageBuffer variance_image() const {
    ImageBuffer img(width, height);
    for (size_t i = 0; i < m2.size(); ++i) img.pixels[i / 3][int(i % 3)] = n > 1 ? float(m2[i] / (n - 1)) : 0.0f;
    return img;
  }
  // The mean over every pixel channel, summed rows from the top.
  double mean_radiance() const {
    double sum = 0;
    for (int row = 0; row < height; ++row)
      for (size_t i = size_t(height - 1 - row) * width * 3; i < size_t(height - row) * width * 3; ++i) sum += mean[i];
    return sum / double(std::max<size_t>(1, mean.size()));
  }
};

// The per-query costs of one render, kept for the medians in meta.json.
struct CostSamples {
  std::vector<double> tests_per_ray, shadow_per_query, closest_tests, shadow_tests;
  void add(const Json& stats) {
    const double closest = stats.num("closest_queries", 0), shadow = stats.num("shadow_queries", 0);
    const double tests = stats.num("primitive_tests", 0), shadow_tests_total = stats.num("shadow_primitive_tests", 0);
    tests_per_ray.push_back(stat_ratio(stats, "primitive_tests", "rays"));
    shadow_per_query.push_back(stat_ratio(stats, "shadow_queries", "closest_queries"));
    closest_tests.push_back(closest > 0 ? (tests - shadow_tests_total) / closest : 0.0);
    shadow_tests.push_back(shadow > 0 ? shadow_tests_total / shadow : 0.0);
  }
};

// The costs of a case measured the way the grader renders it (rules.h's
// render_plan): several renders, each with its share of -s, their counts
// summed before the ratios are taken. One render at the whole -s can cost
// differently per query: from part 5 on, adaptive sampling (-a 32 0.05 by
// default) stops pixels of a 64-sample render early, where renders of 16
// samples take every sample (p8_sun_diffuse: 1.30 shadow rays per query in
// one render of 64, 1.16 in four of 16). render_plan now gives such a case
// its whole -s in each render; the costs follow whatever it plans.
bool add_costs_as_graded(const Case& c, const MakeSettings& s, uint64_t seed, CostSamples* costs,
                         std::string* message) {
  const RenderPlan plan = render_plan(c, false, Rules());
  Json sum;
  for (int k = 0; k < plan.renders; ++k) {
    const std::string dir = s.work_dir + "/" + c.name + "_cost_" + std::to_string(k);
    RenderOutput out = render_case(s.run, plan.c, plan.c.part, seed + uint64_t(k), dir, false);
    std::error_code ec;
    fs::remove_all(dir, ec);
    if (!out.ok || !out.has_stats) {
      *message = "cost run failed: " + (out.ok ? std::string("no statistics") : out.failure);
      return false;
    }
    if (sum.type != Json::Type::Object) sum = pt::json_object();
    for (const char* key : {"rays", "closest_queries", "shadow_queries", "primitive_tests", "shadow_primitive_tests"})
      sum.set(key, pt::json_real(sum.num(key, 0) + out.stats.num(key, 0)));
  }
  costs->add(sum);
  return true;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

// The medians of the costs, as the grader's cost checks read them.
void record_costs(Json* meta, const CostSamples& c) {
  meta->set("tests_per_ray", pt::json_real(median(c.tests_per_ray)))
      .set("shadow_per_query", pt::json_real(median(c.shadow_per_query)))
      .set("closest_tests_per_query", pt::json_real(median(c.closest_tests)))
      .set("shadow_tests_per_query", pt::json_real(median(c.shadow_tests)));
}

// meta.json: one member per line, keys in alphabetical order (a key set
// twice keeps its last value), so that a remade reference diffs cleanly.
std::string meta_text(const Json& meta) {
  std::map<std::string, Json> sorted;
  for (const auto& [key, value] : meta.members) sorted[key] = value;
  Json out = pt::json_object();
  for (const auto& [key, value] : sorted) {
    const bool scalar = value.type != Json::Type::Array && value.type != Json::Type::Object;
    out.set(key, scalar ? value : Json());
  }
  return pt::write_json(out);
}

// What the reference renders of one case gathered.
struct ReferenceRuns {
  Accumulator radiance, rate;
  std::vector<double> seconds, render_seconds;
  CostSamples costs;
  std::vector<ImageBuffer> first_two = std::vector<ImageBuffer>(2);
  std::string failure;  // the first run that failed, if any
  bool deterministic = false;
};

// Renders runs [first, total) of a case, s.jobs at a time, into runs.
void render_reference_batch(const Case& c, const MakeSettings& s, bool want_rate, int first, int total,
                            ReferenceRuns& runs) {
  std::mutex mu;
  std::atomic<int> next{first};
  const auto worker = [&]() {
    for (;;) {
      const int i = next.fetch_add(1);
      if (i >= total) return;
      {
        std::lock_guard<std::mutex> lock(mu);
        if (!runs.failure.empty()) return;
      }
      const std::string run_dir = s.work_dir + "/" + c.name + "_" + std::to_string(i);
      RenderOutput out = render_case(s.run, c, c.part, s.first_seed + uint64_t(i), run_dir, want_rate);
      std::error_code ec;
      fs::remove_all(run_dir, ec);
      std::lock_guard<std::mutex> lock(mu);
      if (!out.ok) {
        runs.failure = "reference run " + std::to_string(i) + " failed: " + out.failure;
        return;
      }
      if (i < 2) runs.first_two[size_t(i)] = out.radiance;
      runs.radiance.add(out.radiance);
      if (want_rate) runs.rate.add(out.rate);
      runs.seconds.push_back(out.seconds);
      if (out.has_stats) {
        runs.render_seconds.push_back(out.stats.num("render_seconds", 0));
        runs.costs.add(out.stats);
      }
    }
  };
  std::vector<std::thread> pool;
  for (int j = 0; j < std::max(1, std::min(s.jobs, total)); ++j) pool.emplace_back(worker);
  for (auto& t : pool) t.join();
}

// Two runs first: when they agree exactly the image is deterministic
// (normal shading at one sample per pixel) and two are all it needs.
void render_reference_runs(const Case& c, const MakeSettings& s, bool want_rate, ReferenceRuns& runs) {
  render_reference_batch(c, s, want_rate, 0, 2, runs);
  runs.deterministic = runs.failure.empty() && runs.first_two[0].pixels == runs.first_two[1].pixels;
  if (runs.failure.empty() && !runs.deterministic && s.runs > 2) render_reference_batch(c, s, want_rate, 2, s.runs, runs);
}

// The BVH's speed-up: one brute-force render, timed against the BVH's.
bool measure_part1(const Case& c, const MakeSettings& s, double* seconds, double* tests_per_ray,
                   std::string* message) {
  RenderOutput p1 = render_case(s.run, c, 1, s.first_seed, s.work_dir + "/" + c.name + "_part1", false);
  if (!p1.ok || !p1.has_stats) {
    *message = "reference --part 1 run failed: " + (p1.ok ? std::string("no statistics") : p1.failure);
    return false;
  }
  *seconds = p1.stats.num("render_seconds", 0);
  *tests_per_ray = stat_ratio(p1.stats, "primitive_tests", "rays");
  return true;
}

// A probability case's picture of the map, by one more render, copied into
// the reference's folder (before meta.json, which marks it complete).
bool make_probability_image(const Case& c, const MakeSettings& s, const std::string& dir, std::string* message) {
  const std::string run_dir = s.work_dir + "/" + c.name + "_probability";
  RenderOutput out = render_case(s.run, with_probability_image(c), c.part, s.first_seed, run_dir, false);
  std::error_code ec;
  fs::create_directories(dir, ec);
  fs::remove(dir + "/meta.json", ec);
  if (out.ok) fs::copy_file(run_dir + "/" + kProbabilityImageFile, dir + "/" + kProbabilityImageFile,
                            fs::copy_options::overwrite_existing, ec);
  if (!out.ok || ec) {
    *message = "reference probability image failed: " + (out.ok ? ec.message() : out.failure);
    return false;
  }
  fs::remove_all(run_dir, ec);
  return true;
}

// Writes the images, then meta.json last: an interrupted write leaves the
// case incomplete, and the next run remakes it. Throws on a failed write.
void write_reference(const std::string& dir, const Case& c, const MakeSettings& s, const ReferenceRuns& runs,
                     bool want_rate, double part1_seconds, double part1_tests_per_ray, pt::Clock::time_point t0) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  fs::remove(dir + "/meta.json", ec);  // incomplete until rewritten
  pt::write_pfm(dir + "/mean.pfm", runs.radiance.mean_image());
  pt::write_pfm(dir + "/variance.pfm", runs.radiance.variance_image());
  if (want_rate) {
    pt::write_pfm(dir + "/rate_mean.pfm", runs.rate.mean_image());
    pt::write_pfm(dir + "/rate_variance.pfm", runs.rate.variance_image());
  }
  Json meta = pt::json_object();
  meta.set("case", pt::json_text(c.name))
      .set("digest", pt::json_text(case_digest(c)))
      .set("command", pt::json_text("pathtracer " + case_command(c) + " -t " + std::to_string(s.run.threads)))
      .set("runs", pt::json_real(runs.radiance.n))
      .set("deterministic", pt::json_bool(runs.deterministic))
      .set("first_seed", pt::json_real(double(s.first_seed)))
      .set("commit", pt::json_text(s.commit))
      .set("date", pt::json_text(utc_now()))
      .set("making_seconds", pt::json_real(pt::seconds_since(t0)))
      .set("process_seconds_median", pt::json_real(median(runs.seconds)))
      .set("render_seconds_median", pt::json_real(median(runs.render_seconds)));
  record_costs(&meta, runs.costs);
  meta.set("costs_as_graded", pt::json_bool(true));
  meta.set("part1_render_seconds", pt::json_real(part1_seconds))
      .set("part1_tests_per_ray", pt::json_real(part1_tests_per_ray))
      .set("mean_radiance", pt::json_real(runs.radiance.mean_radiance()));
  write_text(dir + "/meta.json", meta_text(meta));
}

}  // namespace

bool make_reference(const std::string& root, const Case& c, const MakeSettings& s, std::string* message) {
  const std::string dir = root + "/" + c.name;
  if (!s.force) {
    Reference existing;
    std::string why;
    if (load_reference(root, c, &existing, &why)) {
      *message = "kept (" + std::to_string(existing.runs) + " runs, made " + existing.meta.str("date") + ")";
      return true;
    }
  }
  const bool want_rate = c.kind == CaseKind::Rate;
  const auto t0 = pt::Clock::now();
  ReferenceRuns runs;
  render_reference_runs(c, s, want_rate, runs);
  if (!runs.failure.empty()) {
    *message = runs.failure;
    return false;
  }
  // The costs the grader compares with: three measurements made the way
  // it renders the case, not the reference runs' (one render at the whole -s).
  if (!runs.deterministic) {
    runs.costs = CostSamples();
    for (int i = 0; i < 3; ++i)
      if (!add_costs_as_graded(c, s, s.first_seed + uint64_t(s.runs) + 64 * uint64_t(i), &runs.costs, message))
        return false;
  }
  double part1_seconds = 0, part1_tests_per_ray = 0;
  if (c.kind == CaseKind::Speedup && !measure_part1(c, s, &part1_seconds, &part1_tests_per_ray, message)) return false;
  if (c.kind == CaseKind::Probability && !make_probability_image(c, s, dir, message)) return false;
  try {
    write_reference(dir, c, s, runs, want_rate, part1_seconds, part1_tests_per_ray, t0);
  } catch (const std::exception& e) {
    *message = e.what();
    return false;
  }
  char buf[160];
  std::snprintf(buf, sizeof buf, "%d runs%s, %.1f s", runs.radiance.n, runs.deterministic ? " (deterministic)" : "",
                pt::seconds_since(t0));
  *message = buf;
  return true;
}

bool retime_reference(const std::string& root, const Case& c, const MakeSettings& s, int runs, std::string* message) {
  Reference ref;
  if (!load_reference(root, c, &ref, message)) return false;
  std::vector<double> seconds, render_seconds;
  CostSamples costs;
  double part1 = 0;
  for (int i = 0; i < runs; ++i) {
    // Costs as the grader renders the case (a deterministic case is one
    // render at its settings either way).
    if (ref.deterministic) {
      RenderOutput out = render_case(s.run, c, c.part, s.first_seed + uint64_t(i), s.work_dir + "/" + c.name + "_cost",
                                     false);
      if (!out.ok || !out.has_stats) {
        *message = "cost run failed: " + (out.ok ? std::string("no statistics") : out.failure);
        return false;
      }
      costs.add(out.stats);
    } else if (!add_costs_as_graded(c, s, s.first_seed + 64 * uint64_t(i), &costs, message)) {
      return false;
    }
    if (s.costs_only) continue;
    const std::string dir = s.work_dir + "/" + c.name + "_time";
    RenderOutput out = render_case(s.run, c, c.part, s.first_seed + uint64_t(i), dir, false);
    if (!out.ok || !out.has_stats) {
      *message = "timing run failed: " + (out.ok ? std::string("no statistics") : out.failure);
      return false;
    }
    seconds.push_back(out.seconds);
    render_seconds.push_back(out.stats.num("render_seconds", 0));
  }
  Json& meta = ref.meta;
  record_costs(&meta, costs);
  meta.set("costs_as_graded", pt::json_bool(true));
  if (s.costs_only) {
    try {
      write_text(root + "/" + c.name + "/meta.json", meta_text(meta));
    } catch (const std::exception& e) {
      *message = e.what();
      return false;
    }
    *message = "costs re-measured as graded (" + std::to_string(runs) + " runs), times kept";
    return true;
  }
  if (c.kind == CaseKind::Speedup) {
    RenderOutput p1 = render_case(s.run, c, 1, s.first_seed, s.work_dir + "/" + c.name + "_part1", false);
    if (!p1.ok || !p1.has_stats) {
      *message = "timing run of --part 1 failed: " + (p1.ok ? std::string("no statistics") : p1.failure);
      return false;
    }
    part1 = p1.stats.num("render_seconds", 0);
  }
  meta.set("process_seconds_median", pt::json_real(median(seconds)))
      .set("render_seconds_median", pt::json_real(median(render_seconds)))
      .set("timing_runs", pt::json_real(runs));
  if (c.kind == CaseKind::Speedup) meta.set("part1_render_seconds", pt::json_real(part1));
  meta.set("timing_date", pt::json_text(utc_now()));
  try {
    write_text(root + "/" + c.name + "/meta.json", meta_text(meta));
  } catch (const std::exception& e) {
    *message = e.what();
    return false;
  }
  char buf[120];
  std::snprintf(buf, sizeof buf, "render %.4f s (median of %d)", median(render_seconds), runs);
  *message = buf;
  return true;
}

}  // namespace grader
