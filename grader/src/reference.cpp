#include "reference.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <mutex>
#include <thread>
#include <vector>

#include "text.h"

namespace grader {

namespace fs = std::filesystem;

bool load_reference(const std::string& root, const Case& c, Reference* ref, std::string* why) {
  const std::string dir = root + "/" + c.name;
  if (!fs::exists(dir + "/meta.json")) {
    *why = "no reference in " + dir + " (make it with: grader make-references --case " + c.name + ")";
    return false;
  }
  try {
    ref->meta = read_json_file(dir + "/meta.json");
    if (ref->meta.str("digest") != case_digest(c)) {
      *why = "the reference in " + dir + " was made for another definition of the case (remake it)";
      return false;
    }
    ref->runs = int(ref->meta.num("runs", 0));
    ref->deterministic = ref->meta.flag("deterministic");
    ref->mean = read_pfm_image(dir + "/mean.pfm");
    ref->variance = read_pfm_image(dir + "/variance.pfm");
    if (c.kind == CaseKind::Rate) {
      ref->rate_mean = read_pfm_image(dir + "/rate_mean.pfm");
      ref->rate_variance = read_pfm_image(dir + "/rate_variance.pfm");
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
  int width = 0, height = 0, channels = 0;
  std::vector<double> mean, m2;
  void add(const Image& img) {
    if (n == 0) {
      width = img.width, height = img.height, channels = img.channels;
      mean.assign(img.data.size(), 0.0);
      m2.assign(img.data.size(), 0.0);
    }
    ++n;
    for (size_t i = 0; i < img.data.size(); ++i) {
      const double d = img.data[i] - mean[i];
      mean[i] += d / n;
      m2[i] += d * (img.data[i] - mean[i]);
    }
  }
  Image mean_image() const {
    Image img(width, height, channels);
    for (size_t i = 0; i < mean.size(); ++i) img.data[i] = float(mean[i]);
    return img;
  }
  Image variance_image() const {
    Image img(width, height, channels);
    for (size_t i = 0; i < m2.size(); ++i) img.data[i] = n > 1 ? float(m2[i] / (n - 1)) : 0.0f;
    return img;
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

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

// The medians of the costs, as the grader's cost checks read them.
void record_costs(Json* meta, const CostSamples& c) {
  set_number(meta, "tests_per_ray", median(c.tests_per_ray));
  set_number(meta, "shadow_per_query", median(c.shadow_per_query));
  set_number(meta, "closest_tests_per_query", median(c.closest_tests));
  set_number(meta, "shadow_tests_per_query", median(c.shadow_tests));
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
  const auto t0 = std::chrono::steady_clock::now();

  // Two runs first: when they agree exactly the image is deterministic
  // (normal shading at one sample per pixel) and two are all it needs.
  std::mutex mu;
  Accumulator radiance, rate;
  std::vector<double> seconds, render_seconds;
  CostSamples costs;
  std::vector<Image> first_two(2);
  std::string failure;
  std::atomic<int> next{0};
  const auto worker = [&](int total) {
    for (;;) {
      const int i = next.fetch_add(1);
      if (i >= total) return;
      {
        std::lock_guard<std::mutex> lock(mu);
        if (!failure.empty()) return;
      }
      const std::string run_dir = s.work_dir + "/" + c.name + "_" + std::to_string(i);
      RenderOutput out = render_case(s.run, c, c.part, s.first_seed + uint64_t(i), run_dir, want_rate);
      std::error_code ec;
      fs::remove_all(run_dir, ec);
      std::lock_guard<std::mutex> lock(mu);
      if (!out.ok) {
        failure = "reference run " + std::to_string(i) + " failed: " + out.failure;
        return;
      }
      if (i < 2) first_two[size_t(i)] = out.radiance;
      radiance.add(out.radiance);
      if (want_rate) rate.add(out.rate);
      seconds.push_back(out.seconds);
      if (out.has_stats) {
        render_seconds.push_back(out.stats.num("render_seconds", 0));
        costs.add(out.stats);
      }
    }
  };
  const auto run_batch = [&](int first, int total) {
    next.store(first);
    std::vector<std::thread> pool;
    for (int j = 0; j < std::max(1, std::min(s.jobs, total)); ++j) pool.emplace_back(worker, total);
    for (auto& t : pool) t.join();
  };
  run_batch(0, 2);
  const bool deterministic = failure.empty() && first_two[0].data == first_two[1].data;
  if (failure.empty() && !deterministic && s.runs > 2) run_batch(2, s.runs);
  if (!failure.empty()) {
    *message = failure;
    return false;
  }

  // The BVH's speed-up: one brute-force render, timed against the BVH's.
  double part1_seconds = 0, part1_tests_per_ray = 0;
  if (c.kind == CaseKind::Speedup) {
    RenderOutput p1 = render_case(s.run, c, 1, s.first_seed, s.work_dir + "/" + c.name + "_part1", false);
    if (!p1.ok || !p1.has_stats) {
      *message = "reference --part 1 run failed: " + (p1.ok ? std::string("no statistics") : p1.failure);
      return false;
    }
    part1_seconds = p1.stats.num("render_seconds", 0);
    part1_tests_per_ray = stat_ratio(p1.stats, "primitive_tests", "rays");
  }

  std::error_code ec;
  fs::create_directories(dir, ec);
  fs::remove(dir + "/meta.json", ec);  // incomplete until rewritten
  try {
    write_pfm_image(dir + "/mean.pfm", radiance.mean_image());
    write_pfm_image(dir + "/variance.pfm", radiance.variance_image());
    if (want_rate) {
      write_pfm_image(dir + "/rate_mean.pfm", rate.mean_image());
      write_pfm_image(dir + "/rate_variance.pfm", rate.variance_image());
    }
    double mean_radiance = 0;
    for (double v : radiance.mean) mean_radiance += v;
    mean_radiance /= std::max<size_t>(1, radiance.mean.size());
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    Json meta;
    set_string(&meta, "case", c.name);
    set_string(&meta, "digest", case_digest(c));
    set_string(&meta, "command", "pathtracer " + case_command(c) + " -t " + std::to_string(s.run.threads));
    set_number(&meta, "runs", radiance.n);
    set_bool(&meta, "deterministic", deterministic);
    set_number(&meta, "first_seed", double(s.first_seed));
    set_string(&meta, "commit", s.commit);
    set_string(&meta, "date", utc_now());
    set_number(&meta, "making_seconds", wall);
    set_number(&meta, "process_seconds_median", median(seconds));
    set_number(&meta, "render_seconds_median", median(render_seconds));
    record_costs(&meta, costs);
    set_number(&meta, "part1_render_seconds", part1_seconds);
    set_number(&meta, "part1_tests_per_ray", part1_tests_per_ray);
    set_number(&meta, "mean_radiance", mean_radiance);
    write_text(dir + "/meta.json", flat_json(meta));
  } catch (const std::exception& e) {
    *message = e.what();
    return false;
  }
  char buf[160];
  std::snprintf(buf, sizeof buf, "%d runs%s, %.1f s", radiance.n, deterministic ? " (deterministic)" : "",
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
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
    const std::string dir = s.work_dir + "/" + c.name + "_time";
    RenderOutput out = render_case(s.run, c, c.part, s.first_seed + uint64_t(i), dir, false);
    if (!out.ok || !out.has_stats) {
      *message = "timing run failed: " + (out.ok ? std::string("no statistics") : out.failure);
      return false;
    }
    seconds.push_back(out.seconds);
    render_seconds.push_back(out.stats.num("render_seconds", 0));
    costs.add(out.stats);
  }
  if (c.kind == CaseKind::Speedup) {
    RenderOutput p1 = render_case(s.run, c, 1, s.first_seed, s.work_dir + "/" + c.name + "_part1", false);
    if (!p1.ok || !p1.has_stats) {
      *message = "timing run of --part 1 failed: " + (p1.ok ? std::string("no statistics") : p1.failure);
      return false;
    }
    part1 = p1.stats.num("render_seconds", 0);
  }
  Json& meta = ref.meta;
  set_number(&meta, "process_seconds_median", median(seconds));
  set_number(&meta, "render_seconds_median", median(render_seconds));
  set_number(&meta, "timing_runs", runs);
  record_costs(&meta, costs);
  if (c.kind == CaseKind::Speedup) set_number(&meta, "part1_render_seconds", part1);
  set_string(&meta, "timing_date", utc_now());
  try {
    write_text(root + "/" + c.name + "/meta.json", flat_json(meta));
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
