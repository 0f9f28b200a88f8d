// ray_bench: the speed of the path tracer's ray queries on fixed ray sets,
// one thread, in the shape of ../shared/bench/embree_bench so that the two
// can trace the same files and be compared as a ratio.
//
//   ray_bench SCENE.dae [--out DIR] [--set primary|diffuse|shadow|all]
//             [--rays N] [--reps R] [--width W --height H] [--leaf N]
//             [--bins N] [--seed S] [--engine bvh|brute] [--write-only]
//             [--clock wall|cpu]
//
// Writes DIR/<scene>.tris and DIR/{primary,diffuse,shadow}.rays (see
// ray_files.h and ray_sets.h), then for each selected set prints one block
// of `key: value` lines on stdout: best-of-R closest-hit and occlusion
// passes, and the primitive tests and BVH nodes per ray of one pass.
// Everything else goes to stderr.
#include <algorithm>
#include <charconv>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "stages/part1_raytracing/brute_force.h"
#include "stages/part2_bvh/bvh.h"
#include "common/collada.h"
#include "pathtracer/options.h"
#include "instructors/bench/ray_files.h"
#include "instructors/bench/ray_sets.h"
#include "pathtracer/render_job.h"
#include "common/stats.h"

namespace {

using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;

constexpr const char* kUsage =
    "usage: ray_bench SCENE.dae [--out DIR] [--set primary|diffuse|shadow|all] [--rays N] [--reps R]\n"
    "                 [--width W --height H] [--leaf N] [--bins N] [--seed S] [--engine bvh|brute]\n"
    "                 [--write-only] [--clock wall|cpu]\n";

// Bad input: one line on stderr, exit status 2.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Args {
  std::string scene;
  std::string out_dir;  // empty: bench-out/<scene stem>
  std::string set = "all";
  uint64_t rays = 200000;
  int reps = 5;
  int width = 800, height = 600;
  pt::BVHOptions bvh;
  uint64_t seed = 0;
  bool brute_force = false;
  bool write_only = false;
};

// The timer of the passes: wall-clock time (steady_clock, as embree_bench
// times), or with --clock cpu the calling thread's CPU time, which a busy
// machine disturbs far less (time spent waiting for a core is not counted;
// for comparing two builds of ray_bench with each other, not with Embree).
bool g_cpu_clock = false;
double now_seconds() {
  if (g_cpu_clock) {
    timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
  }
  return std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
}

template <typename T>
T parse_number(const std::string& flag, const char* text, T lo, T hi) {
  T v{};
  const char* end = text + std::strlen(text);
  const auto [ptr, ec] = std::from_chars(text, end, v);
  if (ec != std::errc() || ptr != end || *text == '\0')
    throw UsageError(flag + ": expected an integer, got '" + text + "'");
  if (v < lo || v > hi)
    throw UsageError(flag + ": must be between " + std::to_string(lo) + " and " + std::to_string(hi) +
                     ", got " + text);
  return v;
}

Args parse_args(int argc, char** argv) {
  Args a;
  bool have_scene = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&]() -> const char* {
      if (i + 1 >= argc) throw UsageError(arg + ": missing value");
      return argv[++i];
    };
    if (arg == "-h" || arg == "--help") {
      std::fputs(kUsage, stdout);
      std::exit(0);
    } else if (arg == "--out") {
      a.out_dir = value();
      if (a.out_dir.empty()) throw UsageError("--out: empty folder name");
    } else if (arg == "--set") {
      a.set = value();
      if (a.set != "primary" && a.set != "diffuse" && a.set != "shadow" && a.set != "all")
        throw UsageError("--set: expected primary, diffuse, shadow or all, got '" + a.set + "'");
    } else if (arg == "--rays") {
      a.rays = parse_number<uint64_t>(arg, value(), 1, uint64_t(1) << 28);
    } else if (arg == "--reps") {
      a.reps = parse_number<int>(arg, value(), 1, 1000);
    } else if (arg == "--width") {
      a.width = parse_number<int>(arg, value(), 1, 16384);
    } else if (arg == "--height") {
      a.height = parse_number<int>(arg, value(), 1, 16384);
    } else if (arg == "--leaf") {
      a.bvh.max_leaf_size = parse_number<int>(arg, value(), 1, 255);
    } else if (arg == "--cost") {
      a.bvh.traversal_cost = parse_number<float>(arg, value(), 0.0f, 100.0f);
    } else if (arg == "--bins") {
      a.bvh.bins = parse_number<int>(arg, value(), 2, 1024);
    } else if (arg == "--seed") {
      a.seed = parse_number<uint64_t>(arg, value(), 0, UINT64_MAX);
    } else if (arg == "--engine") {
      const std::string e = value();
      if (e != "bvh" && e != "brute") throw UsageError("--engine: expected bvh or brute, got '" + e + "'");
      a.brute_force = e == "brute";
    } else if (arg == "--clock") {
      const std::string c = value();
      if (c != "wall" && c != "cpu") throw UsageError("--clock: expected wall or cpu, got '" + c + "'");
      g_cpu_clock = c == "cpu";
    } else if (arg == "--write-only") {
      a.write_only = true;
    } else if (!arg.empty() && arg[0] == '-') {
      throw UsageError("unknown option " + arg);
    } else if (have_scene) {
      throw UsageError("more than one scene given ('" + a.scene + "' and '" + arg + "')");
    } else {
      a.scene = arg;
      have_scene = true;
    }
  }
  if (!have_scene) throw UsageError("no scene file given");
  if (a.out_dir.empty()) a.out_dir = (fs::path("bench-out") / fs::path(a.scene).stem()).string();
  return a;
}

double seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }


struct PassResult {
  double best_seconds = 0;
  uint64_t count = 0;         // closest hits or occluded rays
  double sum_t = 0;           // closest pass only
  double tests_per_ray = 0;   // from the first pass
  double nodes_per_ray = 0;
};

// Best of `reps` closest-hit passes over `rays`.
PassResult closest_pass(const pt::Intersector& isect, const std::vector<pt::bench::RayRecord>& rays, int reps) {
  PassResult res;
  res.best_seconds = 1e30;
  for (int rep = 0; rep < reps; ++rep) {
    pt::thread_ray_stats() = pt::RayStats{};
    uint64_t hits = 0;
    double sum_t = 0;
    const double t0 = now_seconds();
    for (const pt::bench::RayRecord& rec : rays) {
      pt::Ray r = rec.to_ray();
      pt::Hit hit;
      if (isect.intersect(r, &hit)) {
        ++hits;
        sum_t += double(hit.t);
      }
    }
    res.best_seconds = std::min(res.best_seconds, now_seconds() - t0);
    res.count = hits;
    res.sum_t = sum_t;
    if (rep == 0 && !rays.empty()) {
      const pt::RayStats& s = pt::thread_ray_stats();
      res.tests_per_ray = double(s.primitive_tests) / double(rays.size());
      res.nodes_per_ray = double(s.node_visits) / double(rays.size());
    }
  }
  return res;
}

// Best of `reps` occlusion passes over `rays`.
PassResult occlusion_pass(const pt::Intersector& isect, const std::vector<pt::bench::RayRecord>& rays, int reps) {
  PassResult res;
  res.best_seconds = 1e30;
  for (int rep = 0; rep < reps; ++rep) {
    pt::thread_ray_stats() = pt::RayStats{};
    uint64_t occluded = 0;
    const double t0 = now_seconds();
    for (const pt::bench::RayRecord& rec : rays)
      if (isect.occluded(rec.to_ray())) ++occluded;
    res.best_seconds = std::min(res.best_seconds, now_seconds() - t0);
    res.count = occluded;
    if (rep == 0 && !rays.empty()) {
      const pt::RayStats& s = pt::thread_ray_stats();
      res.tests_per_ray = double(s.primitive_tests) / double(rays.size());
      res.nodes_per_ray = double(s.node_visits) / double(rays.size());
    }
  }
  return res;
}

double mrays_per_s(size_t rays, double secs) { return secs > 0 ? double(rays) / secs * 1e-6 : 0.0; }

int run(const Args& args) {
  std::vector<std::string> warnings;
  pt::Scene scene = pt::load_collada(args.scene, &warnings);
  for (const std::string& w : warnings) std::fprintf(stderr, "ray_bench: warning: %s\n", w.c_str());
  if (!scene.spheres.empty())
    throw std::runtime_error(args.scene + ": has " + std::to_string(scene.spheres.size()) +
                             " analytic sphere(s); the .tris file holds triangles only, so another engine "
                             "could not trace the same scene (use a triangle-mesh scene)");
  if (scene.triangles.empty()) throw std::runtime_error(args.scene + ": the scene has no triangles");

  pt::RenderOptions ro;
  ro.width = args.width;
  ro.height = args.height;
  pt::configure_camera(scene.camera, ro);

  // Build: best of --reps on one thread (the figure to set beside Embree's
  // one-thread build), then best of --reps with every core (as the
  // pathtracer builds); the last tree is the one traced (the tree does not
  // depend on the thread count).
  std::unique_ptr<pt::Intersector> isect;
  double build_best = 1e30, build_best_all = 1e30;
  const pt::BVH* bvh = nullptr;
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  for (int threads : {1, 0}) {
    for (int rep = 0; rep < args.reps; ++rep) {
      isect.reset();
      const auto t0 = Clock::now();
      const double c0 = now_seconds();  // --clock cpu: this thread's CPU time (right for the one-thread build)
      if (args.brute_force) {
        isect = std::make_unique<pt::BruteForceIntersector>(scene);
      } else {
        pt::BVHOptions o = args.bvh;
        o.build_threads = threads;
        auto tree = std::make_unique<pt::BVH>(scene, o);
        bvh = tree.get();
        isect = std::move(tree);
      }
      if (threads == 1)
        build_best = std::min(build_best, now_seconds() - c0);
      else
        build_best_all = std::min(build_best_all, seconds(t0, Clock::now()));
    }
  }

  const pt::bench::RaySets sets = pt::bench::make_ray_sets(scene, *isect, args.rays, args.seed);

  // Files for the other engine.
  const fs::path dir(args.out_dir);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) throw std::runtime_error(args.out_dir + ": cannot create output folder");
  const std::string tris_path = (dir / (fs::path(args.scene).stem().string() + ".tris")).string();
  pt::bench::write_tris(tris_path, scene);
  struct Named {
    const char* name;
    const std::vector<pt::bench::RayRecord>* rays;
    std::string path;
  };
  std::vector<Named> all = {{"primary", &sets.primary, ""}, {"diffuse", &sets.diffuse, ""}, {"shadow", &sets.shadow, ""}};
  for (Named& s : all) {
    s.path = (dir / (std::string(s.name) + ".rays")).string();
    pt::bench::write_rays(s.path, *s.rays);
  }
  std::fprintf(stderr, "ray_bench: wrote %s (%zu triangles) and %s/{primary,diffuse,shadow}.rays (%zu, %zu, %zu rays)\n",
               tris_path.c_str(), scene.triangles.size(), dir.string().c_str(), sets.primary.size(),
               sets.diffuse.size(), sets.shadow.size());
  if (scene.lights.empty())
    std::fprintf(stderr, "ray_bench: warning: %s has no lights, so the shadow set is empty\n", args.scene.c_str());
  if (args.write_only) return 0;

  char engine[160];
  if (args.brute_force)
    std::snprintf(engine, sizeof engine, "pathtracer brute force (every ray tests every triangle, 1 thread)");
  else
    std::snprintf(engine, sizeof engine, "pathtracer BVH (binned SAH, %d bins, leaf <= %d, 1 thread)", args.bvh.bins,
                  args.bvh.max_leaf_size);

  bool first = true;
  for (const Named& s : all) {
    if (args.set != "all" && args.set != s.name) continue;
    if (s.rays->empty()) {
      std::fprintf(stderr, "ray_bench: the %s set is empty; skipped\n", s.name);
      continue;
    }
    const PassResult c = closest_pass(*isect, *s.rays, args.reps);
    const PassResult o = occlusion_pass(*isect, *s.rays, args.reps);
    if (!first) std::printf("\n");
    first = false;
    std::printf("engine: %s\n", engine);
    std::printf("scene: %s\n", args.scene.c_str());
    std::printf("ray_set: %s\n", s.name);
    std::printf("rays_file: %s\n", s.path.c_str());
    std::printf("tris_file: %s\n", tris_path.c_str());
    std::printf("triangles: %zu\n", scene.triangles.size());
    std::printf("rays: %zu\n", s.rays->size());
    std::printf("build_ms: %.3f\n", build_best * 1e3);
    std::printf("build_all_threads_ms: %.3f\n", build_best_all * 1e3);
    std::printf("build_threads: %u\n", cores);
    if (bvh) {
      const pt::BVHBuildStats& bs = bvh->build_stats();
      std::printf("bvh_nodes: %zu\n", bs.nodes);
      std::printf("bvh_leaves: %zu\n", bs.leaves);
      std::printf("bvh_depth: %d\n", bs.depth);
      std::printf("bvh_sah_cost: %.3f\n", bs.sah_cost);
    }
    std::printf("closest_hits: %llu\n", (unsigned long long)c.count);
    std::printf("closest_sum_t: %.6e\n", c.sum_t);
    std::printf("closest_mrays_per_s: %.3f\n", mrays_per_s(s.rays->size(), c.best_seconds));
    std::printf("closest_tests_per_ray: %.3f\n", c.tests_per_ray);
    std::printf("closest_nodes_per_ray: %.3f\n", c.nodes_per_ray);
    std::printf("occluded: %llu\n", (unsigned long long)o.count);
    std::printf("anyhit_mrays_per_s: %.3f\n", mrays_per_s(s.rays->size(), o.best_seconds));
    std::printf("anyhit_tests_per_ray: %.3f\n", o.tests_per_ray);
    std::printf("anyhit_nodes_per_ray: %.3f\n", o.nodes_per_ray);
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(parse_args(argc, argv));
  } catch (const UsageError& e) {
    std::fprintf(stderr, "ray_bench: error: %s (run 'ray_bench --help' for usage)\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ray_bench: error: %s\n", e.what());
    return 1;
  }
}
