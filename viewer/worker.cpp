#include "viewer/worker.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <new>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "stages/part2_bvh/bvh.h"
#include "stages/part1_raytracing/camera_rays.h"
#include "common/collada.h"
#include "common/math_constants.h"
#include "viewer/debug_api.h"
#include "viewer/debugger/debugger.h"
#include "pathtracer/options.h"
#include "pathtracer/render_job.h"
#include "common/todo.h"
#include "viewer/progressive.h"
#include "viewer/worker_watch.h"

namespace pt::viewer {

#ifdef PT_VIEWER_PLANTS
// Outside the unnamed namespace, so that a report can name them.
__attribute__((noinline, noipa)) void planted_crash_in_render(volatile int* p) { *p = 1; }
__attribute__((noinline, noipa)) void planted_crash_in_debug_tool(volatile int* p) { *p = 1; }
// A recursion that never ends: the stack overflows.
__attribute__((noinline, noipa)) int planted_endless_recursion(volatile int* depth) {
  volatile char frame[256];
  frame[0] = char(*depth);
  ++*depth;
  return *depth >= 0 ? planted_endless_recursion(depth) + frame[0] : 0;
}
// A loop that never ends (until the worker is killed).
__attribute__((noinline, noipa)) void planted_infinite_loop_in_render(volatile int* spin) {
  while (*spin) {
  }
}
__attribute__((noinline, noipa)) void planted_infinite_loop_in_debug_tool(volatile int* spin) {
  while (*spin) {
  }
}
#endif

namespace {

int g_protocol_fd = -1;  // the worker's real standard output

// A job that has not moved on for this long is reported stuck (an endless
// loop in a part's code, most likely): a STALL line (worker_watch.h).
constexpr double kStallSeconds = 5.0;

void write_all(const void* data, size_t n) {
  const char* p = static_cast<const char*>(data);
  while (n > 0) {
    const ssize_t w = ::write(g_protocol_fd, p, n);
    if (w < 0) {
      if (errno == EINTR) continue;
      std::_Exit(3);  // the server went away: nothing left to do
    }
    p += w;
    n -= size_t(w);
  }
}

void write_message(const std::string& head, const std::vector<uint8_t>& payload) {
  write_all(head.data(), head.size());
  if (!payload.empty()) write_all(payload.data(), payload.size());
}

#ifdef PT_VIEWER_PLANTS
// Test builds only: faults planted by the environment, to test how the
// server reports them. PT_VIEWER_PLANT=crash dereferences a null pointer
// in the middle of a render with --seed 13 and throws an exception there
// with --seed 14 (and in every Debug mode call with --seed 13), and
// dereferences it in every pixel with --seed 16 (every render thread
// crashes at once), and recurses until the stack overflows with --seed 17;
// =hang loops for ever in the middle of a render with
// --seed 15 (and in every Debug mode call with --seed 15); =todo prints a
// stub's TODO line; =gate starts each pass after the first only once the
// file $PT_VIEWER_GATE<pass> exists; =pi sends every frame's radiance
// times pi (what a diffuse BSDF that leaves out the division by pi gives
// under direct light).
std::string planted() {
  const char* v = std::getenv("PT_VIEWER_PLANT");
  return v ? v : "";
}
#endif

std::string frame_json(const RenderOptions& o, int pass, const RenderResult& r, double elapsed, uint64_t traced,
                       uint64_t reused, size_t bytes) {
  char buf[768];
  std::snprintf(buf, sizeof buf,
                "{\"kind\":\"render\",\"pass\":%d,\"width\":%d,\"height\":%d,\"samples\":%d,"
                "\"rays\":%llu,\"tests\":%llu,\"nodes\":%llu,\"seconds\":%.6f,\"elapsed\":%.6f,"
                "\"traced\":%llu,\"reused\":%llu,\"used_bvh\":%s,\"bytes\":%zu}",
                pass, o.width, o.height, o.samples_per_pixel, (unsigned long long)r.stats.rays(),
                (unsigned long long)r.stats.primitive_tests, (unsigned long long)r.stats.node_visits, r.seconds,
                elapsed, (unsigned long long)traced, (unsigned long long)reused, r.used_bvh ? "true" : "false", bytes);
  return buf;
}

// A pass's frame: its image, the samples each pixel took and its tests per
// ray, written as they are converted (no copy of the image).
void write_frame(const std::string& head, const ImageBuffer& img, const std::vector<float>& tests,
                 const std::vector<uint32_t>& rays) {
  write_all(head.data(), head.size());
  std::vector<uint8_t> chunk;
  chunk.reserve(20 << 12);
  for (size_t i = 0; i < img.pixels.size(); ++i) {
    uint8_t p[20];
    const float per_ray = rays[i] ? tests[i] / float(rays[i]) : 0.0f;
    std::memcpy(p, &img.pixels[i], 12);
    std::memcpy(p + 12, &img.samples[i], 4);
    std::memcpy(p + 16, &per_ray, 4);
    chunk.insert(chunk.end(), p, p + 20);
    if (chunk.size() >= (20 << 12)) {
      write_all(chunk.data(), chunk.size());
      chunk.clear();
    }
  }
  if (!chunk.empty()) write_all(chunk.data(), chunk.size());
}

Scene load_scene(const RenderOptions& o) {
  std::vector<std::string> warnings;
  Scene scene = load_collada(o.scene_path, &warnings);
  if (!o.env_map.empty()) {
    Light env;
    env.type = LightType::Environment;
    env.environment = std::make_shared<const EnvironmentMap>(load_environment_map(o.env_map));
    scene.lights.push_back(env);
  }
  configure_camera(scene.camera, o);
  return scene;
}

// The progressive render (progressive.h): passes of 1, 2, 4, ... samples,
// then -s, each the command line's render at its count, each pass reusing
// the samples of the one before; a frame after each.
int run_render(const RenderOptions& base) {
  const Scene scene = load_scene(base);
  const int w = base.width, h = base.height;
  const auto t0 = std::chrono::steady_clock::now();
  // Per pixel, the intersection tests and rays of the samples in the
  // image shown: pass 1's own, then those of every jittered sample so far.
  std::vector<float> tests(size_t(w) * h, 0.0f);
  std::vector<uint32_t> rays(size_t(w) * h, 0);
  struct Last {
    int pass = -1;
    RayStats stats;
  };
  std::atomic<uint64_t> pixels_done{0};
  const StallWatch watch(pixels_done, kStallSeconds);
  PassHooks hooks;
  hooks.before_pixel = [](int, int, int) { prepare_thread_for_faults(); };
  hooks.after_pixel = [&](int pass, int x, int y) {
    // The render loop zeroes each thread's counters when a render starts.
    thread_local Last last;
    if (last.pass != pass) last = Last{pass, RayStats{}};
    const RayStats& now = thread_ray_stats();
    const size_t i = size_t(y) * w + x;
    rays[i] += uint32_t(now.rays() - last.stats.rays());
    tests[i] += float(now.primitive_tests - last.stats.primitive_tests);
    last.stats = now;
#ifdef PT_VIEWER_PLANTS
    const uint64_t seed = base.seed;
    if (seed == 13 && x == w / 2 && y == h / 2 && planted() == "crash") planted_crash_in_render(nullptr);
    if (seed == 14 && x == w / 2 && y == h / 2 && planted() == "crash")
      throw std::runtime_error("planted failure: a part threw an exception");
    if (seed == 15 && x == w / 2 && y == h / 2 && planted() == "hang") {
      volatile int spin = 1;
      planted_infinite_loop_in_render(&spin);
    }
    if (seed == 16 && planted() == "crash") planted_crash_in_render(nullptr);
    if (seed == 17 && x == w / 2 && y == h / 2 && planted() == "crash") {
      volatile int depth = 0;
      planted_endless_recursion(&depth);
    }
#endif
    ++pixels_done;
  };
  hooks.pass_done = [&](int pass, const RenderOptions& o, const RenderResult& r, uint64_t traced, uint64_t reused) {
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const size_t bytes = size_t(w) * h * 20;
    const ImageBuffer* image = &r.image;
#ifdef PT_VIEWER_PLANTS
    ImageBuffer brighter;
    if (planted() == "pi") {
      brighter = r.image;
      for (Color& c : brighter.pixels) c = c * kPi;
      image = &brighter;
    }
#endif
    write_frame("FRAME " + frame_json(o, pass, r, elapsed, traced, reused, bytes) + "\n", *image, tests, rays);
    // From the second pass on, the maps add up the jittered samples only.
    if (pass == 0) {
      std::fill(tests.begin(), tests.end(), 0.0f);
      std::fill(rays.begin(), rays.end(), 0u);
    }
#ifdef PT_VIEWER_PLANTS
    // The next pass waits until the test lets it (a file <gate><pass> exists).
    if (planted() == "gate" && o.samples_per_pixel < base.samples_per_pixel)
      while (!std::filesystem::exists(std::getenv("PT_VIEWER_GATE") + std::to_string(pass + 1)))
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
#endif
  };
  prepare_thread_for_faults();
  render_progressive(scene, base, hooks);
  write_message("DONE\n", {});
  return 0;
}

// Slab test of a ray against a box within [t0, t1].
bool box_hit(const BVHNode& n, const Ray& r, float t0, float t1) {
  for (int a = 0; a < 3; ++a) {
    const float inv = 1.0f / r.d[a];
    float tn = (n.lo[a] - r.o[a]) * inv, tf = (n.hi[a] - r.o[a]) * inv;
    if (tn > tf) std::swap(tn, tf);
    if (std::isnan(tn) || std::isnan(tf)) continue;  // a zero direction inside the slab
    t0 = std::max(t0, tn);
    t1 = std::min(t1, tf);
    if (t0 > t1) return false;
  }
  return true;
}

// The BVH of the scene, as the part's code builds it, and for every node
// how many of the camera's pixel-centre rays reach its box before their
// nearest hit (the rays any correct traversal must take into it).
// Payload: nodes x 32 bytes (BVHNode), then leaf primitive ids (uint32),
// then the ray counts per node (uint32).
int run_bvh(const RenderOptions& o) {
  const Scene scene = load_scene(o);
  BVHOptions bo;
  bo.max_leaf_size = o.bvh_max_leaf;
  bo.bins = o.bvh_bins;
  const BVH bvh(scene, bo);
  const auto& nodes = bvh.nodes();
  const auto& prims = bvh.leaf_primitives();
  std::vector<uint32_t> entered(nodes.size(), 0);
  const Camera& cam = scene.camera;
  std::vector<uint32_t> stack;
  for (int y = 0; y < o.height; ++y)
    for (int x = 0; x < o.width; ++x) {
      Ray r = generate_ray(cam, (x + 0.5) / o.width, (y + 0.5) / o.height);
      Hit hit;
      bvh.intersect(r, &hit);  // sets r.max_t to the nearest hit
      if (nodes.empty()) continue;
      stack.assign(1, 0);
      while (!stack.empty()) {
        const uint32_t i = stack.back();
        stack.pop_back();
        if (i >= nodes.size() || !box_hit(nodes[i], r, r.min_t, r.max_t)) continue;
        ++entered[i];
        if (!nodes[i].is_leaf() && nodes[i].first + 1 < nodes.size()) {
          stack.push_back(nodes[i].first);
          stack.push_back(nodes[i].first + 1);
        }
      }
    }
  std::vector<uint8_t> payload(nodes.size() * 32 + prims.size() * 4 + entered.size() * 4);
  uint8_t* p = payload.data();
  if (!nodes.empty()) std::memcpy(p, nodes.data(), nodes.size() * 32);
  p += nodes.size() * 32;
  if (!prims.empty()) std::memcpy(p, prims.data(), prims.size() * 4);
  p += prims.size() * 4;
  if (!entered.empty()) std::memcpy(p, entered.data(), entered.size() * 4);
  const BVHBuildStats& st = bvh.build_stats();
  char head[512];
  std::snprintf(head, sizeof head,
                "BVH {\"nodes\":%zu,\"prims\":%zu,\"triangles\":%zu,\"spheres\":%zu,\"build_seconds\":%.6f,"
                "\"sah_cost\":%.6f,\"depth\":%d,\"leaves\":%zu,\"camera_rays\":%lld,\"bytes\":%zu}\n",
                nodes.size(), prims.size(), scene.triangles.size(), scene.spheres.size(), st.build_seconds,
                st.sah_cost, st.depth, st.leaves, (long long)o.width * o.height, payload.size());
  write_message(head, payload);
  write_message("DONE\n", {});
  return 0;
}

// One call of the Debug mode's tools: "RESULT {status, bytes}" and the
// result's JSON (status 200), or the reason absurd input was refused (400).
int run_debug(const std::string& tool, const std::string& input, const RenderOptions& o) {
  int status = 200;
  std::string body;
  const std::atomic<uint64_t> no_progress{0};  // a call is one step: stuck once it takes long
  const StallWatch watch(no_progress, kStallSeconds);
#ifdef PT_VIEWER_PLANTS
  if (planted() == "crash" && o.seed == 13) planted_crash_in_debug_tool(nullptr);
  if (planted() == "hang" && o.seed == 15) {
    volatile int spin = 1;
    planted_infinite_loop_in_debug_tool(&spin);
  }
#endif
  try {
    body = run_debug_tool(tool, input, o, [&] { return load_scene(o); });
  } catch (const debug::InputError& e) {
    status = 400;
    body = std::string("{\"error\":") + json_quote(e.what()) + "}";
  }
  write_message("RESULT {\"status\":" + std::to_string(status) + ",\"bytes\":" + std::to_string(body.size()) + "}\n",
                std::vector<uint8_t>(body.begin(), body.end()));
  write_message("DONE\n", {});
  return 0;
}

}  // namespace

int worker_main(int argc, char** argv) {
  // The protocol keeps the real stdout; everything the program prints goes
  // to stderr, where the server reads the TODO lines.
  g_protocol_fd = ::dup(1);
  ::dup2(2, 1);
  install_fault_handlers();
  if (argc < 3) {
    std::fprintf(stderr, "ERROR the worker needs a job\n");
    return 2;
  }
  const std::string job = argv[2];
  // A debug job: "--worker debug TOOL INPUT flags... scene".
  const int first_flag = job == "debug" ? 5 : 3;
  if (first_flag > argc) {
    std::fprintf(stderr, "ERROR the debug job needs a tool and its input\n");
    return 2;
  }
  // parse_command_line sees "viewer <flags> scene".
  std::vector<char*> args = {argv[0]};
  for (int i = first_flag; i < argc; ++i) args.push_back(argv[i]);
  try {
    RenderOptions opts;
    if (auto code = parse_command_line(int(args.size()), args.data(), &opts)) {
      std::fprintf(stderr, "ERROR the settings were refused (see above)\n");
      return *code;
    }
#ifdef PT_VIEWER_PLANTS
    if (planted() == "todo") todo_once("Part 1: raytrace_pixel (stages/part1_raytracing/pixel_sampling.cpp); one sample through the pixel centre, whatever -s");
#endif
    if (job == "render") return run_render(opts);
    if (job == "bvh") return run_bvh(opts);
    if (job == "debug") return run_debug(argv[3], argv[4], opts);
    std::fprintf(stderr, "ERROR unknown worker job '%s'\n", job.c_str());
    return 2;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "ERROR out of memory\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ERROR %s\n", e.what());
  }
  return 1;
}

}  // namespace pt::viewer
