#include "reference.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <mutex>
#include <sstream>
#include <thread>
#include <vector>

#include "image_io.h"

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

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

std::string utc_now() {
  const std::time_t t = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return buf;
}

// What a cost check compares: intersection tests per ray, and shadow rays
// per closest-hit query (camera rays and bounces).
double stat_ratio(const Json& stats, const char* num, const char* den) {
  const double d = stats.num(den, 0);
  return d > 0 ? stats.num(num, 0) / d : 0.0;
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
  std::vector<double> seconds, render_seconds, tests_per_ray, shadow_per_query;
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
        tests_per_ray.push_back(stat_ratio(out.stats, "primitive_tests", "rays"));
        shadow_per_query.push_back(stat_ratio(out.stats, "shadow_queries", "closest_queries"));
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
    std::ostringstream js;
    js << "{\n"
       << "  \"case\": " << json_quote(c.name) << ",\n"
       << "  \"digest\": " << json_quote(case_digest(c)) << ",\n"
       << "  \"command\": " << json_quote("pathtracer " + case_command(c) + " -t " + std::to_string(s.run.threads)) << ",\n"
       << "  \"runs\": " << radiance.n << ",\n"
       << "  \"deterministic\": " << (deterministic ? "true" : "false") << ",\n"
       << "  \"first_seed\": " << s.first_seed << ",\n"
       << "  \"commit\": " << json_quote(s.commit) << ",\n"
       << "  \"date\": " << json_quote(utc_now()) << ",\n"
       << "  \"making_seconds\": " << json_number(wall) << ",\n"
       << "  \"process_seconds_median\": " << json_number(median(seconds)) << ",\n"
       << "  \"render_seconds_median\": " << json_number(median(render_seconds)) << ",\n"
       << "  \"tests_per_ray\": " << json_number(median(tests_per_ray)) << ",\n"
       << "  \"shadow_per_query\": " << json_number(median(shadow_per_query)) << ",\n"
       << "  \"part1_render_seconds\": " << json_number(part1_seconds) << ",\n"
       << "  \"part1_tests_per_ray\": " << json_number(part1_tests_per_ray) << ",\n"
       << "  \"mean_radiance\": " << json_number(mean_radiance) << "\n"
       << "}\n";
    const std::string text = js.str();
    pt::write_file_atomically(dir + "/meta.json", std::vector<uint8_t>(text.begin(), text.end()));
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

namespace {

// meta.json is a flat object: numbers, strings and booleans.
std::string flat_json(const Json& j) {
  std::string out = "{\n";
  size_t i = 0;
  for (const auto& [key, v] : j.object) {
    out += "  " + json_quote(key) + ": ";
    if (v.type == Json::Type::String) out += json_quote(v.string);
    else if (v.type == Json::Type::Bool) out += v.boolean ? "true" : "false";
    else if (v.type == Json::Type::Number) out += json_number(v.number);
    else out += "null";
    out += ++i < j.object.size() ? ",\n" : "\n";
  }
  return out + "}\n";
}

}  // namespace

bool retime_reference(const std::string& root, const Case& c, const MakeSettings& s, int runs, std::string* message) {
  Reference ref;
  if (!load_reference(root, c, &ref, message)) return false;
  std::vector<double> seconds, render_seconds;
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
  const auto set_number = [&](const char* key, double v) {
    Json n;
    n.type = Json::Type::Number;
    n.number = v;
    meta.object[key] = n;
  };
  set_number("process_seconds_median", median(seconds));
  set_number("render_seconds_median", median(render_seconds));
  set_number("timing_runs", runs);
  if (c.kind == CaseKind::Speedup) set_number("part1_render_seconds", part1);
  Json date;
  date.type = Json::Type::String;
  date.string = utc_now();
  meta.object["timing_date"] = date;
  try {
    const std::string text = flat_json(meta);
    pt::write_file_atomically(root + "/" + c.name + "/meta.json", std::vector<uint8_t>(text.begin(), text.end()));
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
