#include "server.h"

#include <cxxabi.h>
#include <cerrno>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <random>
#include <sstream>
#include <thread>
#include <vector>

#include <httplib.h>

#include "camera_file.h"
#include "case_list.h"
#include "collada.h"
#include "debug_api.h"
#include "grade.h"
#include "pictures.h"
#include "reference.h"
#include "image_io.h"
#include "json.h"
#include "render_job.h"

extern char** environ;

namespace pt::viewer {

namespace fs = std::filesystem;

namespace {

std::string num(double v) { return pt::json_number(v); }

// ---------------------------------------------------------------- requests

// A bad request: the message goes to the page with status 400 (or `status`).
struct BadRequest : std::runtime_error {
  int status;
  explicit BadRequest(const std::string& m, int s = 400) : std::runtime_error(m), status(s) {}
};

// Reads members of the JSON object the page sends, checking each as the
// command line checks its flag (absent or null: the fallback).
class SettingsReader {
 public:
  explicit SettingsReader(const Json& j) : j_(j) {}

  double number(const char* key, double lo, double hi, double fallback, bool integer) {
    const Json* v = j_.get(key);
    if (!v || v->type == Json::Type::Null) return fallback;
    if (v->type != Json::Type::Number || !std::isfinite(v->number))
      throw BadRequest(std::string(key) + ": expected a number");
    if (integer && v->number != std::floor(v->number)) throw BadRequest(std::string(key) + ": expected an integer");
    if (v->number < lo || v->number > hi) {
      char buf[160];
      std::snprintf(buf, sizeof buf, "%s: %.10g is outside [%.10g, %.10g]", key, v->number, lo, hi);
      throw BadRequest(buf);
    }
    return v->number;
  }
  bool flag(const char* key, bool fallback) {
    const Json* v = j_.get(key);
    if (!v || v->type == Json::Type::Null) return fallback;
    if (v->type != Json::Type::Bool) throw BadRequest(std::string(key) + ": expected true or false");
    return v->boolean;
  }
  std::string text(const char* key, const std::string& fallback) {
    const Json* v = j_.get(key);
    if (!v || v->type == Json::Type::Null) return fallback;
    if (v->type != Json::Type::String) throw BadRequest(std::string(key) + ": expected a string");
    return v->string;
  }
  std::vector<double> numbers(const char* key, const Json& obj, size_t n) {
    const Json* v = obj.get(key);
    if (!v || v->type != Json::Type::Array || v->array.size() != n)
      throw BadRequest(std::string(key) + ": expected " + std::to_string(n) + " numbers");
    std::vector<double> out;
    for (const Json& e : v->array) {
      if (e.type != Json::Type::Number || !std::isfinite(e.number) || std::fabs(e.number) > 1e12)
        throw BadRequest(std::string(key) + ": expected " + std::to_string(n) + " finite numbers");
      out.push_back(e.number);
    }
    return out;
  }

  const Json& json() const { return j_; }

 private:
  const Json& j_;
};

struct CameraOverride {
  bool set = false;
  Vec3d position, target, up;
};

// The render the page asks for, as options and as the worker's flags.
struct Request {
  RenderOptions opts;
  CameraOverride camera;
};

Request read_request(const Json& j, const RenderOptions& start, const FileAccess& files) {
  if (j.type != Json::Type::Object) throw BadRequest("expected a JSON object");
  SettingsReader r(j);
  Request q;
  RenderOptions& o = q.opts;
  o = start;
  o.output_png.clear();
  o.output_pfm.clear();
  o.stats_json.clear();
  o.cell_set = false;
  std::string why;
  const std::string scene = r.text("scene", start.scene_path);
  o.scene_path = files.resolve(scene, FileKind::Scene, &why);
  if (o.scene_path.empty()) throw BadRequest(why, 403);
  const std::string cam = r.text("camera_file", start.camera_settings);
  o.camera_settings.clear();
  if (!cam.empty()) {
    o.camera_settings = files.resolve(cam, FileKind::Camera, &why);
    if (o.camera_settings.empty()) throw BadRequest(why, 403);
  }
  const std::string env = r.text("env", start.env_map);
  o.env_map.clear();
  if (!env.empty()) {
    o.env_map = files.resolve(env, FileKind::Environment, &why);
    if (o.env_map.empty()) throw BadRequest(why, 403);
  }
  o.part = int(r.number("part", 1, kPartsBuilt, start.part, true));
  o.samples_per_pixel = int(r.number("samples", 1, 1 << 20, start.samples_per_pixel, true));
  o.light_samples = int(r.number("light_samples", 1, 1 << 16, start.light_samples, true));
  o.max_depth = int(r.number("max_depth", 0, 1 << 20, start.max_depth, true));
  o.accumulate_bounces = r.flag("accumulate", start.accumulate_bounces);
  o.hemisphere_sampling = r.flag("hemisphere", start.hemisphere_sampling);
  o.threads = int(r.number("threads", 1, 256, start.threads, true));
  o.adaptive_batch = int(r.number("adaptive_batch", 1, 1 << 20, start.adaptive_batch, true));
  o.adaptive_tolerance = r.number("adaptive_tolerance", 1e-9, 1e9, start.adaptive_tolerance, false);
  o.adaptive_set = true;
  const double lens = r.number("lens_radius", 0, 1e6, start.lens_radius_set ? start.lens_radius : -1, false);
  o.lens_radius_set = lens >= 0;
  if (o.lens_radius_set) o.lens_radius = lens;
  const double focal = r.number("focal_distance", 1e-6, 1e9, start.focal_distance_set ? start.focal_distance : -1, false);
  o.focal_distance_set = focal > 0;
  if (o.focal_distance_set) o.focal_distance = focal;
  o.width = int(r.number("width", 1, 16384, start.width, true));
  o.height = int(r.number("height", 1, 16384, start.height, true));
  if ((long long)o.width * o.height > kMaxImagePixels)
    throw BadRequest("width x height: at most " + std::to_string(kMaxImagePixels) + " pixels");
  // A seed beyond 2^53 does not survive a JSON number: it may come as a string.
  if (const Json* sd = j.get("seed"); sd && sd->type == Json::Type::String) {
    const std::string& t = sd->string;
    errno = 0;
    char* end = nullptr;
    const unsigned long long v = std::strtoull(t.c_str(), &end, 10);
    if (t.empty() || t.size() > 20 || t.find_first_not_of("0123456789") != std::string::npos || errno == ERANGE ||
        *end != '\0')
      throw BadRequest("seed: expected an integer from 0 to 18446744073709551615");
    o.seed = v;
  } else {
    o.seed = uint64_t(r.number("seed", 0, 9007199254740991.0, double(start.seed), true));
  }
  o.bvh_max_leaf = int(r.number("bvh_leaf", 1, 255, start.bvh_max_leaf, true));
  o.bvh_bins = int(r.number("bvh_bins", 2, 64, start.bvh_bins, true));
  if (const Json* c = j.get("cell"); c && c->type != Json::Type::Null) {
    const std::vector<double> v = r.numbers("cell", j, 4);
    for (double x : v)
      if (x != std::floor(x)) throw BadRequest("cell: expected 4 integers");
    if (v[0] < 0 || v[1] < 0 || v[2] < 1 || v[3] < 1 || v[0] + v[2] > o.width || v[1] + v[3] > o.height)
      throw BadRequest("cell: must lie inside the " + std::to_string(o.width) + "x" + std::to_string(o.height) +
                       " image and be at least 1x1");
    o.cell_set = true;
    o.cell_x = int(v[0]);
    o.cell_y = int(v[1]);
    o.cell_w = int(v[2]);
    o.cell_h = int(v[3]);
  }
  if (const Json* c = j.get("camera"); c && c->type != Json::Type::Null) {
    if (c->type != Json::Type::Object) throw BadRequest("camera: expected an object");
    const auto p = r.numbers("position", *c, 3), t = r.numbers("target", *c, 3), u = r.numbers("up", *c, 3);
    q.camera.set = true;
    q.camera.position = Vec3d(p[0], p[1], p[2]);
    q.camera.target = Vec3d(t[0], t[1], t[2]);
    q.camera.up = Vec3d(u[0], u[1], u[2]);
    if (!(norm(q.camera.position - q.camera.target) > 1e-9)) throw BadRequest("camera: position and target coincide");
    if (!(norm(q.camera.up) > 1e-9)) throw BadRequest("camera: up is zero");
  }
  return q;
}

// The flags that make the command line render `o` (no output files).
std::vector<std::string> render_flags(const RenderOptions& o) {
  std::vector<std::string> a = {"--part", std::to_string(o.part),
                                "-s", std::to_string(o.samples_per_pixel),
                                "-l", std::to_string(o.light_samples),
                                "-m", std::to_string(o.max_depth),
                                "-o", o.accumulate_bounces ? "1" : "0",
                                "-t", std::to_string(o.threads),
                                "-r", std::to_string(o.width), std::to_string(o.height),
                                "--seed", std::to_string(o.seed),
                                "--bvh-leaf", std::to_string(o.bvh_max_leaf),
                                "--bvh-bins", std::to_string(o.bvh_bins)};
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", o.adaptive_tolerance);
  a.insert(a.end(), {"-a", std::to_string(o.adaptive_batch), buf});
  if (o.hemisphere_sampling) a.push_back("-H");
  if (o.lens_radius_set) {
    std::snprintf(buf, sizeof buf, "%.17g", o.lens_radius);
    a.insert(a.end(), {"-b", buf});
  }
  if (o.focal_distance_set) {
    std::snprintf(buf, sizeof buf, "%.17g", o.focal_distance);
    a.insert(a.end(), {"-d", buf});
  }
  if (!o.camera_settings.empty()) a.insert(a.end(), {"-c", o.camera_settings});
  if (!o.env_map.empty()) a.insert(a.end(), {"-e", o.env_map});
  if (o.cell_set)
    a.insert(a.end(), {"-p", std::to_string(o.cell_x), std::to_string(o.cell_y), std::to_string(o.cell_w),
                       std::to_string(o.cell_h)});
  if (!o.russian_roulette) a.push_back("--no-rr");
  if (o.direct_only) a.push_back("--direct-only");
  if (o.indirect_only) a.push_back("--indirect-only");
  if (o.course_area_pdf) a.push_back("--course-area-pdf");
  a.push_back("--no-progress");
  a.push_back(o.scene_path);
  return a;
}

std::string settings_json(const RenderOptions& o) {
  std::ostringstream s;
  s << "{\"scene\":" << json_quote(o.scene_path) << ",\"part\":" << o.part << ",\"samples\":" << o.samples_per_pixel
    << ",\"light_samples\":" << o.light_samples << ",\"max_depth\":" << o.max_depth
    << ",\"accumulate\":" << (o.accumulate_bounces ? "true" : "false")
    << ",\"hemisphere\":" << (o.hemisphere_sampling ? "true" : "false") << ",\"threads\":" << o.threads
    << ",\"adaptive_batch\":" << o.adaptive_batch << ",\"adaptive_tolerance\":" << num(o.adaptive_tolerance)
    << ",\"lens_radius\":" << (o.lens_radius_set ? num(o.lens_radius) : "null")
    << ",\"focal_distance\":" << (o.focal_distance_set ? num(o.focal_distance) : "null")
    << ",\"width\":" << o.width << ",\"height\":" << o.height << ",\"seed\":"
    << (o.seed > 9007199254740991ull ? json_quote(std::to_string(o.seed)) : std::to_string(o.seed))
    << ",\"bvh_leaf\":" << o.bvh_max_leaf << ",\"bvh_bins\":" << o.bvh_bins
    << ",\"camera_file\":" << json_quote(o.camera_settings) << ",\"env\":" << json_quote(o.env_map) << ",\"cell\":";
  if (o.cell_set)
    s << "[" << o.cell_x << "," << o.cell_y << "," << o.cell_w << "," << o.cell_h << "]";
  else
    s << "null";
  s << "}";
  return s.str();
}

std::string vec_json(const Vec3d& v) { return "[" + num(v.x) + "," + num(v.y) + "," + num(v.z) + "]"; }

// ---------------------------------------------------------------- workers

struct Frame {
  std::string kind;  // "render"
  Json head;
  int width = 0, height = 0, samples = 0, pass = 0;
  std::vector<uint8_t> payload;  // 20 bytes per pixel (worker.h)

  ImageBuffer image() const {
    ImageBuffer img(width, height);
    for (size_t i = 0; i < img.pixels.size(); ++i) {
      std::memcpy(&img.pixels[i], &payload[i * 20], 12);
      std::memcpy(&img.samples[i], &payload[i * 20 + 12], 4);
    }
    return img;
  }
  float tests(size_t i) const {
    float t;
    std::memcpy(&t, &payload[i * 20 + 16], 4);
    return t;
  }
};

// One worker process and what it has said.
struct Job {
  uint64_t id = 0;
  std::string kind;  // "render", "normals" (one pass of normal shading) or "bvh"
  RenderOptions opts;
  pid_t pid = -1;

  std::mutex mu;
  std::condition_variable cv;
  std::string state = "running";  // running, done, failed, crashed, cancelled
  std::string message;
  std::vector<std::string> todo;      // "Part 1: raytrace_pixel (stages/...)"
  std::vector<std::string> log;       // the last lines of its stderr
  std::shared_ptr<const Frame> frame; // the latest render pass
  int frames = 0;
  std::vector<int> passes;            // the samples per pixel of every pass so far
  std::string bvh_head;               // the BVH message's JSON
  std::shared_ptr<const std::vector<uint8_t>> bvh;
  int result_status = 0;              // a debug job's answer: HTTP status and JSON
  std::string result;
  bool cancel_requested = false;
  std::string crash_signal, crash_function;
  double started = 0;
  double last_seen = 0;  // the last status request for it
};

double now_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

bool read_exact(int fd, void* data, size_t n) {
  char* p = static_cast<char*>(data);
  while (n > 0) {
    const ssize_t r = ::read(fd, p, n);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) return false;
    p += r;
    n -= size_t(r);
  }
  return true;
}

bool read_line(int fd, std::string* line, size_t limit = 1 << 16) {
  line->clear();
  char c;
  while (true) {
    const ssize_t r = ::read(fd, &c, 1);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) return false;
    if (c == '\n') return true;
    if (line->size() < limit) line->push_back(c);
  }
}

// "viewer(_ZN2pt18intersect_triangleERKNS_3RayE+0x2a) [0x55d1]" -> "intersect_triangle".
std::string frame_function(const std::string& line) {
  const size_t open = line.find('('), plus = line.find('+', open == std::string::npos ? 0 : open);
  if (open == std::string::npos || plus == std::string::npos || plus <= open + 1) return "";
  const std::string mangled = line.substr(open + 1, plus - open - 1);
  int status = 0;
  char* d = abi::__cxa_demangle(mangled.c_str(), nullptr, nullptr, &status);
  if (status != 0 || !d) {
    std::free(d);
    return "";
  }
  std::string name = d;
  std::free(d);
  if (name.rfind("pt::", 0) != 0) return "";
  if (name.find("on_fault") != std::string::npos) return "";
  // Drop the parameter list and the namespaces.
  int depth = 0;
  size_t cut = name.size();
  for (size_t i = 0; i < name.size(); ++i) {
    if (name[i] == '(' && depth == 0) {
      cut = i;
      break;
    }
    if (name[i] == '<') ++depth;
    if (name[i] == '>') --depth;
  }
  name = name.substr(0, cut);
  const size_t colons = name.rfind("::");
  return colons == std::string::npos ? name : name.substr(colons + 2);
}

class Workers {
 public:
  Workers(std::string exe) : exe_(std::move(exe)) {}

  // Starts a job of `kind` ("render", "normals" or "bvh") for `opts` with
  // `flags`; it replaces (and stops) the running job of the same kind.
  std::shared_ptr<Job> start(const std::string& kind, const RenderOptions& opts, const std::vector<std::string>& flags) {
    auto job = std::make_shared<Job>();
    job->kind = kind;
    job->opts = opts;
    job->started = job->last_seen = now_seconds();
    {
      std::lock_guard<std::mutex> lock(mu_);
      job->id = ++next_id_;
      // One job of each kind at a time: a new one stops the one before.
      auto& previous = latest_[kind];
      if (previous) cancel(previous);
      previous = job;
      if (kind == "render") current_ = job;
      jobs_[job->id] = job;
      // Keep the last few jobs' results for the page (and every kind's
      // latest); forget the rest.
      for (auto it = jobs_.begin(); jobs_.size() > 8 && it != jobs_.end();) {
        bool latest = false;
        for (const auto& [k, j] : latest_) latest = latest || j == it->second;
        it = latest ? std::next(it) : jobs_.erase(it);
      }
    }
    std::vector<std::string> args = {exe_, "--worker", kind == "normals" ? "render" : kind};
    args.insert(args.end(), flags.begin(), flags.end());
    int out[2], err[2];
    if (pipe2(out, O_CLOEXEC) != 0) throw std::runtime_error("cannot create a pipe");
    if (pipe2(err, O_CLOEXEC) != 0) {
      ::close(out[0]);
      ::close(out[1]);
      throw std::runtime_error("cannot create a pipe");
    }
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_adddup2(&fa, out[1], 1);
    posix_spawn_file_actions_adddup2(&fa, err[1], 2);
    posix_spawn_file_actions_addclosefrom_np(&fa, 3);
    posix_spawnattr_t attr;
    posix_spawnattr_init(&attr);
    // Its own process group, so that anything it starts dies with it.
    posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETPGROUP);
    posix_spawnattr_setpgroup(&attr, 0);
    pid_t pid = -1;
    const int rc = posix_spawn(&pid, exe_.c_str(), &fa, &attr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&fa);
    posix_spawnattr_destroy(&attr);
    ::close(out[1]);
    ::close(err[1]);
    if (rc != 0) {
      ::close(out[0]);
      ::close(err[0]);
      std::lock_guard<std::mutex> lock(job->mu);
      job->state = "failed";
      job->message = "cannot start the worker " + exe_ + ": " + std::strerror(rc);
      return job;
    }
    {
      std::lock_guard<std::mutex> lock(job->mu);
      job->pid = pid;
    }
    std::thread([job, o = out[0], e = err[0]] { watch(job, o, e); }).detach();
    return job;
  }

  std::shared_ptr<Job> find(uint64_t id) {
    std::lock_guard<std::mutex> lock(mu_);
    auto it = jobs_.find(id);
    return it == jobs_.end() ? nullptr : it->second;
  }
  std::shared_ptr<Job> current() {
    std::lock_guard<std::mutex> lock(mu_);
    return current_;
  }
  void stop_current() {
    std::lock_guard<std::mutex> lock(mu_);
    if (current_) cancel(current_);
  }
  // Stops the current render when no page has asked about it for
  // `seconds`: a closed tab leaves no render running.
  void stop_unwatched(double seconds) {
    std::lock_guard<std::mutex> lock(mu_);
    if (!current_) return;
    bool stale;
    {
      std::lock_guard<std::mutex> jl(current_->mu);
      stale = current_->state == "running" && now_seconds() - current_->last_seen > seconds;
    }
    if (stale) cancel(current_);
  }
  void stop_all() {
    std::lock_guard<std::mutex> lock(mu_);
    for (auto& [id, job] : jobs_) cancel(job);
  }

  static void cancel(const std::shared_ptr<Job>& job) {
    std::lock_guard<std::mutex> lock(job->mu);
    if (job->state != "running") return;
    job->cancel_requested = true;
    if (job->pid > 0) ::kill(-job->pid, SIGKILL);
  }

 private:
  // Reads the worker's two streams until it ends, then records how it ended.
  static void watch(std::shared_ptr<Job> job, int out_fd, int err_fd) {
    std::thread err_reader([job, err_fd] {
      std::string line;
      bool in_backtrace = false;
      while (read_line(err_fd, &line)) {
        std::lock_guard<std::mutex> lock(job->mu);
        if (line.rfind("TODO: implement ", 0) == 0) {
          const std::string what = line.substr(16);
          if (std::find(job->todo.begin(), job->todo.end(), what) == job->todo.end()) job->todo.push_back(what);
          job->cv.notify_all();
        } else if (line.rfind("CRASH ", 0) == 0) {
          job->crash_signal = line.substr(6);
          in_backtrace = true;
        } else if (in_backtrace) {
          if (job->crash_function.empty()) job->crash_function = frame_function(line);
        } else if (line.rfind("ERROR ", 0) == 0) {
          if (job->message.empty()) job->message = line.substr(6);
        } else if (line.rfind("pathtracer: error: ", 0) == 0) {
          job->message = line.substr(19);
        }
        if (!in_backtrace) {
          job->log.push_back(line);
          if (job->log.size() > 20) job->log.erase(job->log.begin());
        }
      }
      ::close(err_fd);
    });
    bool done = false;
    std::string line;
    while (read_line(out_fd, &line)) {
      if (line == "DONE") {
        done = true;
        continue;
      }
      const size_t space = line.find(' ');
      if (space == std::string::npos) break;
      const std::string tag = line.substr(0, space);
      Json head;
      try {
        head = pt::parse_json(line.substr(space + 1), "worker message");
      } catch (const std::exception&) {
        break;
      }
      const double bytes = head.num("bytes", -1);
      if (!(bytes >= 0 && bytes < 4e9)) break;
      auto payload = std::make_shared<std::vector<uint8_t>>(size_t(bytes));
      if (!read_exact(out_fd, payload->data(), payload->size())) break;
      if (tag == "FRAME") {
        auto f = std::make_shared<Frame>();
        f->kind = head.str("kind", "render");
        f->width = int(head.num("width"));
        f->height = int(head.num("height"));
        f->samples = int(head.num("samples"));
        f->pass = int(head.num("pass"));
        if (size_t(f->width) * size_t(f->height) * 20 != payload->size()) break;
        f->payload = std::move(*payload);
        f->head = std::move(head);
        std::lock_guard<std::mutex> lock(job->mu);
        job->passes.push_back(f->samples);
        job->frame = std::move(f);
        ++job->frames;
        job->cv.notify_all();
      } else if (tag == "BVH") {
        std::lock_guard<std::mutex> lock(job->mu);
        job->bvh_head = line.substr(space + 1);
        job->bvh = payload;
      } else if (tag == "RESULT") {
        std::lock_guard<std::mutex> lock(job->mu);
        job->result_status = int(head.num("status", 500));
        job->result.assign(payload->begin(), payload->end());
      }
    }
    ::close(out_fd);
    err_reader.join();
    pid_t pid;
    {
      std::lock_guard<std::mutex> lock(job->mu);
      pid = job->pid;
    }
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    ::kill(-pid, SIGKILL);  // anything it left behind in its group
    std::lock_guard<std::mutex> lock(job->mu);
    const std::string doing = job->kind == "bvh" ? "building the BVH" : job->kind == "debug" ? "debugging" : "rendering";
    if (job->cancel_requested) {
      job->state = "cancelled";
    } else if (WIFSIGNALED(status)) {
      job->state = "crashed";
      const std::string sig = !job->crash_signal.empty() ? job->crash_signal : strsignal(WTERMSIG(status));
      const std::string who = job->crash_function.empty() ? "the worker" : job->crash_function;
      job->message = who + " crashed: " + sig + " while " + doing;
    } else if (WIFEXITED(status) && WEXITSTATUS(status) == 0 && done) {
      job->state = "done";
    } else {
      job->state = "failed";
      if (job->message.empty())
        job->message = "the worker stopped while " + doing + " (exit status " +
                       std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + ")";
    }
    job->cv.notify_all();
  }

  std::string exe_;
  std::mutex mu_;
  uint64_t next_id_ = 0;
  std::map<uint64_t, std::shared_ptr<Job>> jobs_;
  std::map<std::string, std::shared_ptr<Job>> latest_;  // by kind
  std::shared_ptr<Job> current_;                        // the render
};

// ------------------------------------------------------------------ scenes

// Scenes read by the server itself (the loader is given code, not a part's)
// for the page's 3D views: geometry and the camera.
class SceneCache {
 public:
  std::shared_ptr<const Scene> get(const std::string& path) {
    std::lock_guard<std::mutex> lock(mu_);
    if (scene_ && path_ == path) return scene_;
    auto s = std::make_shared<Scene>(load_collada(path));
    path_ = path;
    scene_ = s;
    return s;
  }

 private:
  std::mutex mu_;
  std::string path_;
  std::shared_ptr<const Scene> scene_;
};

// The camera a render of `q` uses: the scene's, with -r, -c, -b, -d, then
// the page's orbit when it sent one.
Camera request_camera(const Scene& scene, const Request& q) {
  Camera cam = scene.camera;
  configure_camera(cam, q.opts);
  if (q.camera.set) cam.look_at(q.camera.position, q.camera.target, q.camera.up);
  return cam;
}

std::string camera_json(const Camera& c) {
  return "{\"position\":" + vec_json(c.position) + ",\"target\":" + vec_json(c.target) +
         ",\"axis_x\":" + vec_json(c.axis_x) + ",\"axis_y\":" + vec_json(c.axis_y) +
         ",\"axis_z\":" + vec_json(c.axis_z) + ",\"hfov\":" + num(c.hfov_deg) + ",\"vfov\":" + num(c.vfov_deg) +
         ",\"near\":" + num(c.near_clip) + ",\"far\":" + num(c.far_clip) + ",\"width\":" + std::to_string(c.width) +
         ",\"height\":" + std::to_string(c.height) + ",\"lens_radius\":" + num(c.lens_radius) +
         ",\"focal_distance\":" + num(c.focal_distance) + "}";
}

// ------------------------------------------------------------------ cases

// A grading case as the viewer's settings: its part and options on its
// scene (when the page may open it).
struct ViewerCase {
  grader::Case c;
  RenderOptions opts;
  bool available = false;  // its scene is in an allowed folder
};

std::vector<ViewerCase> load_cases(const std::string& source_dir, const FileAccess& files) {
  std::vector<ViewerCase> out;
  std::vector<grader::Case> cases;
  try {
    cases = grader::read_cases(source_dir + "/grader/cases.txt");
  } catch (const std::exception&) {
    return out;
  }
  for (const grader::Case& c : cases) {
    if (c.kind != grader::CaseKind::Image) continue;
    std::vector<std::string> args = {"viewer", "--part", std::to_string(c.part)};
    args.insert(args.end(), c.options.begin(), c.options.end());
    args.push_back(source_dir + "/scenes/" + c.scene);
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    ViewerCase v;
    v.c = c;
    if (parse_command_line(int(argv.size()), argv.data(), &v.opts)) continue;
    std::string why;
    const std::string scene = files.resolve(v.opts.scene_path, FileKind::Scene, &why);
    v.available = !scene.empty();
    if (v.available) v.opts.scene_path = scene;
    out.push_back(v);
  }
  return out;
}

// What decides a render's image (not the threads, the seed or the BVH's
// build settings): a render compares with a case when these agree.
std::string image_key(RenderOptions o) {
  o.threads = 1;
  o.seed = 0;
  o.bvh_max_leaf = 4;
  o.bvh_bins = 12;
  o.adaptive_set = true;
  const std::vector<std::string> f = render_flags(o);
  std::string k;
  for (const std::string& a : f) k += a + " ";
  return k;
}

// ------------------------------------------------------------------ server

struct App {
  ServerConfig cfg;
  Workers workers;
  SceneCache scenes;
  std::string temp_dir;
  std::atomic<uint64_t> camera_files{0};
  std::vector<ViewerCase> cases;

  explicit App(ServerConfig c) : cfg(std::move(c)), workers(cfg.worker_exe) {}
};

void send_json(httplib::Response& res, const std::string& body, int status = 200) {
  res.status = status;
  res.set_content(body, "application/json");
  res.set_header("Cache-Control", "no-store");
}

void send_error(httplib::Response& res, const std::string& message, int status) {
  send_json(res, "{\"error\":" + json_quote(message) + "}", status);
}

Json body_json(const httplib::Request& req) {
  try {
    return pt::parse_json(req.body, "request");
  } catch (const std::exception& e) {
    throw BadRequest(std::string("malformed JSON: ") + e.what());
  }
}

uint64_t param_u64(const httplib::Request& req, const char* key) {
  const std::string v = req.get_param_value(key);
  if (v.empty() || v.size() > 19 || v.find_first_not_of("0123456789") != std::string::npos)
    throw BadRequest(std::string(key) + ": expected a non-negative integer");
  return std::stoull(v);
}

std::string job_json(Job& job) {
  // Called with job.mu held.
  std::ostringstream s;
  s << "{\"job\":" << job.id << ",\"kind\":" << json_quote(job.kind) << ",\"state\":" << json_quote(job.state)
    << ",\"message\":" << json_quote(job.message) << ",\"frames\":" << job.frames << ",\"todo\":[";
  for (size_t i = 0; i < job.todo.size(); ++i) s << (i ? "," : "") << json_quote(job.todo[i]);
  s << "],\"log\":[";
  for (size_t i = 0; i < job.log.size(); ++i) s << (i ? "," : "") << json_quote(job.log[i]);
  s << "],\"passes\":[";
  for (size_t i = 0; i < job.passes.size(); ++i) s << (i ? "," : "") << job.passes[i];
  s << "],\"target\":" << job.opts.samples_per_pixel << ",\"settings\":" << settings_json(job.opts);
  if (job.frame) {
    const Json& h = job.frame->head;
    s << ",\"frame\":{\"pass\":" << job.frame->pass << ",\"samples\":" << job.frame->samples
      << ",\"width\":" << job.frame->width << ",\"height\":" << job.frame->height << ",\"rays\":" << num(h.num("rays"))
      << ",\"tests\":" << num(h.num("tests")) << ",\"nodes\":" << num(h.num("nodes"))
      << ",\"seconds\":" << num(h.num("seconds")) << ",\"elapsed\":" << num(h.num("elapsed"))
      << ",\"used_bvh\":" << (h.flag("used_bvh") ? "true" : "false") << "}";
  }
  s << ",\"wall\":" << num(now_seconds() - job.started) << "}";
  return s.str();
}

}  // namespace

std::string random_token() {
  std::random_device rd;  // /dev/urandom
  std::string t;
  const char* hex = "0123456789abcdef";
  for (int i = 0; i < 32; ++i) t += hex[rd() & 15];
  return t;
}


namespace {

// The overlays, as 8-bit RGB rows from the top (the page draws them).
std::vector<uint8_t> flip_to_rgb(int w, int h, const std::function<void(size_t i, uint8_t rgb[3])>& colour) {
  std::vector<uint8_t> out(size_t(w) * h * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) colour(size_t(y) * w + x, &out[(size_t(h - 1 - y) * w + x) * 3]);
  return out;
}

bool token_ok(const httplib::Request& req, const std::string& token) {
  auto same = [&](const std::string& t) {
    if (t.size() != token.size()) return false;
    unsigned diff = 0;
    for (size_t i = 0; i < t.size(); ++i) diff |= unsigned(t[i] ^ token[i]);
    return diff == 0;
  };
  if (req.has_param("token") && same(req.get_param_value("token"))) return true;
  if (req.has_header("X-Token") && same(req.get_header_value("X-Token"))) return true;
  const std::string cookies = req.get_header_value("Cookie");
  size_t at = 0;
  while ((at = cookies.find("pt_viewer_token=", at)) != std::string::npos) {
    at += 16;
    const size_t end = cookies.find(';', at);
    if (same(cookies.substr(at, end == std::string::npos ? std::string::npos : end - at))) return true;
  }
  return false;
}

bool read_file(const std::string& path, std::string* out) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::ostringstream s;
  s << in.rdbuf();
  *out = s.str();
  return true;
}

std::string files_json(const FileAccess& files, FileKind kind) {
  std::string s = "[";
  for (const std::string& f : files.list(kind)) s += (s.size() > 1 ? "," : "") + json_quote(f);
  return s + "]";
}

// httplib compresses text/* and a few exact types with brotli at its
// slowest setting when the browser accepts it: seven seconds for three.js.
// The files are local, so compression buys nothing; this spelling of the
// JavaScript type is not on httplib's list.
constexpr const char* kJavaScript = "application/javascript; charset=utf-8";

std::atomic<bool> g_stop{false};
httplib::Server* g_server = nullptr;

void on_signal(int) {
  g_stop = true;
  if (g_server) g_server->stop();
}

// Runs `handler`, turning bad requests and failures into a JSON error.
template <class F>
httplib::Server::Handler guarded(F handler) {
  return [handler](const httplib::Request& req, httplib::Response& res) {
    try {
      handler(req, res);
    } catch (const BadRequest& e) {
      send_error(res, e.what(), e.status);
    } catch (const std::bad_alloc&) {
      send_error(res, "out of memory", 500);
    } catch (const std::exception& e) {
      send_error(res, e.what(), 500);
    }
  };
}

}  // namespace

int run_server(ServerConfig cfg) {
  if (cfg.token.empty()) cfg.token = random_token();
  App app(std::move(cfg));
  const ServerConfig& c = app.cfg;
  app.cases = load_cases(c.source_dir, c.files);
  {
    char tmpl[] = "/tmp/pt-viewer-XXXXXX";
    if (!::mkdtemp(tmpl)) {
      std::fprintf(stderr, "viewer: error: cannot create a temporary folder\n");
      return 1;
    }
    app.temp_dir = tmpl;
  }
  const std::string three = c.web_dir + "/node_modules/three";
  if (!fs::exists(three + "/build/three.module.js"))
    std::fprintf(stderr,
                 "viewer: warning: %s is missing: the 3D views need it (run scripts/setup.sh, which runs npm ci "
                 "in viewer/web)\n",
                 three.c_str());

  httplib::Server svr;
  g_server = &svr;
  svr.set_payload_max_length(1 << 16);
  // A browser keeps several connections open and the page long-polls on
  // one: enough threads that an idle kept-alive connection never starves
  // a request, and idle connections let go soon.
  svr.new_task_queue = [] { return new httplib::ThreadPool(32); };
  svr.set_keep_alive_timeout(2);
  svr.set_pre_routing_handler([&c](const httplib::Request& req, httplib::Response& res) {
    if (!token_ok(req, c.token)) {
      res.status = 403;
      res.set_content("403: this viewer needs the token of the URL it printed when it started\n", "text/plain");
      return httplib::Server::HandlerResponse::Handled;
    }
    return httplib::Server::HandlerResponse::Unhandled;
  });
  svr.set_error_handler([](const httplib::Request&, httplib::Response& res) {
    if (res.body.empty()) res.set_content("{\"error\":\"HTTP " + std::to_string(res.status) + "\"}", "application/json");
  });

  auto serve_file = [](httplib::Response& res, const std::string& path, const char* type) {
    std::string body;
    if (!read_file(path, &body)) {
      send_error(res, path + ": missing (run scripts/setup.sh)", 404);
      return;
    }
    res.set_content(body, type);
    res.set_header("Cache-Control", "no-cache");
  };
  svr.Get("/", [&](const httplib::Request&, httplib::Response& res) {
    serve_file(res, c.web_dir + "/index.html", "text/html; charset=utf-8");
    res.set_header("Set-Cookie", "pt_viewer_token=" + c.token + "; Path=/; HttpOnly; SameSite=Strict");
  });
  svr.Get(R"(/web/([a-z0-9_]+)\.(js|css))", [&](const httplib::Request& req, httplib::Response& res) {
    const std::string ext = req.matches[2];
    serve_file(res, c.web_dir + "/" + std::string(req.matches[1]) + "." + ext,
               ext == "js" ? kJavaScript : "text/css; charset=utf-8");
  });
  svr.Get("/three/three.module.js", [&](const httplib::Request&, httplib::Response& res) {
    serve_file(res, three + "/build/three.module.js", kJavaScript);
  });

  svr.Get("/api/state", guarded([&](const httplib::Request&, httplib::Response& res) {
    std::ostringstream s;
    s << "{\"start\":" << settings_json(c.start) << ",\"parts_built\":" << kPartsBuilt
      << ",\"scenes\":" << files_json(c.files, FileKind::Scene)
      << ",\"cameras\":" << files_json(c.files, FileKind::Camera)
      << ",\"envs\":" << files_json(c.files, FileKind::Environment) << ",\"folders\":[";
    for (size_t i = 0; i < c.files.folders().size(); ++i) s << (i ? "," : "") << json_quote(c.files.folders()[i]);
    s << "],\"cases\":[";
    bool first = true;
    for (const ViewerCase& vc : app.cases) {
      if (!vc.available) continue;
      s << (first ? "" : ",") << "{\"name\":" << json_quote(vc.c.name) << ",\"settings\":" << settings_json(vc.opts) << "}";
      first = false;
    }
    s << "],\"three\":" << (fs::exists(three + "/build/three.module.js") ? "true" : "false") << "}";
    send_json(res, s.str());
  }));

  // The scene as the page draws it: camera (with the settings applied),
  // bounds, counts; /api/mesh gives its triangles and spheres.
  svr.Post("/api/scene", guarded([&](const httplib::Request& req, httplib::Response& res) {
    const Request q = read_request(body_json(req), c.start, c.files);
    std::shared_ptr<const Scene> scene;
    try {
      scene = app.scenes.get(q.opts.scene_path);
    } catch (const std::exception& e) {
      throw BadRequest(e.what(), 422);
    }
    Camera cam;
    try {
      cam = request_camera(*scene, q);
    } catch (const std::exception& e) {
      throw BadRequest(e.what(), 422);
    }
    const BBox b = scene->bounds();
    std::ostringstream s;
    s << "{\"scene\":" << json_quote(q.opts.scene_path) << ",\"camera\":" << camera_json(cam)
      << ",\"default_camera\":" << camera_json([&] { Camera d = scene->camera; configure_camera(d, q.opts); return d; }())
      << ",\"bounds\":{\"lo\":" << vec_json(Vec3d(b.lo)) << ",\"hi\":" << vec_json(Vec3d(b.hi)) << "}"
      << ",\"triangles\":" << scene->triangles.size() << ",\"spheres\":" << scene->spheres.size()
      << ",\"lights\":" << scene->lights.size() << "}";
    send_json(res, s.str());
  }));
  svr.Post("/api/mesh", guarded([&](const httplib::Request& req, httplib::Response& res) {
    const Request q = read_request(body_json(req), c.start, c.files);
    std::shared_ptr<const Scene> scene;
    try {
      scene = app.scenes.get(q.opts.scene_path);
    } catch (const std::exception& e) {
      throw BadRequest(e.what(), 422);
    }
    // uint32 triangles, uint32 spheres, then 9 floats per triangle (its
    // corners), 9 per triangle (its vertex normals, the shading normals),
    // 4 (centre, radius) per sphere, and an RGB byte triple per triangle
    // and per sphere: the material's colour (emission scaled to 1, else
    // the diffuse albedo).
    const uint32_t nt = uint32_t(scene->triangles.size()), ns = uint32_t(scene->spheres.size());
    std::string body(8 + size_t(nt) * 72 + size_t(ns) * 16, '\0');
    std::string colours;
    auto colour = [&](int material) {
      Color c(0.5f);
      if (material >= 0 && size_t(material) < scene->materials.size()) {
        const Material& m = scene->materials[size_t(material)];
        if (m.is_emissive()) {
          const float k = std::max({m.emission.x, m.emission.y, m.emission.z});
          c = m.emission / k;
        } else {
          c = m.albedo;
        }
      }
      for (int ch = 0; ch < 3; ++ch) colours.push_back(char(std::lround(255 * std::clamp(c[ch], 0.0f, 1.0f))));
    };
    for (const Triangle& t : scene->triangles) colour(t.material);
    for (const Sphere& sp : scene->spheres) colour(sp.material);
    char* p = body.data();
    std::memcpy(p, &nt, 4);
    std::memcpy(p + 4, &ns, 4);
    p += 8;
    for (const Triangle& t : scene->triangles) {
      const float v[9] = {t.p1.x, t.p1.y, t.p1.z, t.p2.x, t.p2.y, t.p2.z, t.p3.x, t.p3.y, t.p3.z};
      std::memcpy(p, v, 36);
      p += 36;
    }
    for (const Triangle& t : scene->triangles) {
      const float n[9] = {t.n1.x, t.n1.y, t.n1.z, t.n2.x, t.n2.y, t.n2.z, t.n3.x, t.n3.y, t.n3.z};
      std::memcpy(p, n, 36);
      p += 36;
    }
    for (const Sphere& sp : scene->spheres) {
      const float v[4] = {sp.center.x, sp.center.y, sp.center.z, sp.radius};
      std::memcpy(p, v, 16);
      p += 16;
    }
    body += colours;
    res.set_content(body, "application/octet-stream");
  }));

  // The course's camera settings file for the page's view.
  svr.Post("/api/camera-file", guarded([&](const httplib::Request& req, httplib::Response& res) {
    const Request q = read_request(body_json(req), c.start, c.files);
    Camera cam;
    try {
      cam = request_camera(*app.scenes.get(q.opts.scene_path), q);
    } catch (const std::exception& e) {
      throw BadRequest(e.what(), 422);
    }
    res.set_content(camera_settings_text(cam), "text/plain");
    res.set_header("Content-Disposition", "attachment; filename=\"camera.txt\"");
  }));

  // Starts a render (cancelling the running one) or a BVH build.
  // Starts a worker job of `kind` for the page's settings `body`; `pre`
  // goes before the flags (a debug job's tool and input).
  auto launch = [&](const std::string& kind, const Json& body, const std::vector<std::string>& pre) {
    Request q = read_request(body, c.start, c.files);
    if (kind == "normals") {
      q.opts.part = std::min(q.opts.part, 2);
      q.opts.samples_per_pixel = 1;
      q.opts.cell_set = false;
    }
    if (q.camera.set) {
      // The page's view becomes a -c file, read the way the command line
      // reads one (the file "save camera" downloads).
      Camera cam;
      try {
        cam = request_camera(*app.scenes.get(q.opts.scene_path), q);
      } catch (const std::exception& e) {
        throw BadRequest(e.what(), 422);
      }
      const std::string path = app.temp_dir + "/camera_" + std::to_string(++app.camera_files) + ".txt";
      std::ofstream(path) << camera_settings_text(cam);
      q.opts.camera_settings = path;
    }
    std::vector<std::string> flags = pre;
    for (const std::string& f : render_flags(q.opts)) flags.push_back(f);
    return app.workers.start(kind, q.opts, flags);
  };
  auto start_job = [&](const std::string& kind, const httplib::Request& req, httplib::Response& res) {
    auto job = launch(kind, body_json(req), {});
    std::lock_guard<std::mutex> lock(job->mu);
    send_json(res, job_json(*job));
  };
  // Debug mode (debug_api.h): one tool's call in a worker with the page's
  // settings; answers with the tool's result, the reason its input was
  // refused (400), or how the worker ended (a crash names the function).
  svr.Post(R"(/api/debug/([a-z]+))", guarded([&](const httplib::Request& req, httplib::Response& res) {
    const std::string tool = req.matches[1];
    if (!is_debug_tool(tool)) throw BadRequest("no debug tool named '" + tool + "'", 404);
    const Json body = body_json(req);
    const Json* in = body.get("debug");
    if (!in || in->type != Json::Type::Object) throw BadRequest("debug: expected the tool's input (an object)");
    auto job = launch("debug", body, {tool, write_json(*in)});
    std::unique_lock<std::mutex> lock(job->mu);
    const bool ended = job->cv.wait_for(lock, std::chrono::seconds(300), [&] { return job->state != "running" || g_stop; });
    std::string todo = "[";
    for (size_t i = 0; i < job->todo.size(); ++i) todo += (i ? "," : "") + json_quote(job->todo[i]);
    if (job->state == "done" && job->result_status > 0) {
      // The TODO lines the worker printed (outside the tool's own record), as "worker_todo".
      std::string body = job->result;
      if (!job->todo.empty() && body.size() > 2 && body[0] == '{') body.insert(1, "\"worker_todo\":" + todo + "],");
      return send_json(res, body, job->result_status);
    }
    const std::string message = !ended ? "the debugger took more than 300 s (stopped)"
                                : job->state == "cancelled" ? "replaced by a newer Debug mode call"
                                : job->message;
    const int status = job->state == "cancelled" && ended ? 409 : 500;
    const std::string state = job->state;
    lock.unlock();
    if (!ended) Workers::cancel(job);
    send_json(res, "{\"error\":" + json_quote(message) + ",\"state\":" + json_quote(state) + ",\"todo\":" + todo + "]}",
              status);
  }));
  svr.Post("/api/render", guarded([&](const httplib::Request& req, httplib::Response& res) { start_job("render", req, res); }));
  svr.Post("/api/normals", guarded([&](const httplib::Request& req, httplib::Response& res) { start_job("normals", req, res); }));
  svr.Post("/api/bvh", guarded([&](const httplib::Request& req, httplib::Response& res) { start_job("bvh", req, res); }));
  svr.Post("/api/stop", guarded([&](const httplib::Request&, httplib::Response& res) {
    app.workers.stop_current();
    send_json(res, "{}");
  }));

  auto find_job = [&](const httplib::Request& req) {
    auto job = app.workers.find(param_u64(req, "job"));
    if (!job) throw BadRequest("no such job (it may have been replaced by newer ones)", 404);
    return job;
  };
  // Waits (up to 10 s) until the job has more than `after` frames or has ended.
  svr.Get("/api/status", guarded([&](const httplib::Request& req, httplib::Response& res) {
    auto job = find_job(req);
    const long long after = req.has_param("after") ? (long long)param_u64(req, "after") : -1;
    std::unique_lock<std::mutex> lock(job->mu);
    job->last_seen = now_seconds();
    job->cv.wait_for(lock, std::chrono::seconds(10),
                     [&] { return job->state != "running" || job->frames > after || g_stop; });
    job->last_seen = now_seconds();
    send_json(res, job_json(*job));
  }));
  auto job_frame = [&](const httplib::Request& req) {
    auto job = find_job(req);
    std::lock_guard<std::mutex> lock(job->mu);
    if (!job->frame) throw BadRequest("no frame yet", 404);
    return std::make_pair(job, job->frame);
  };
  svr.Get("/api/image", guarded([&](const httplib::Request& req, httplib::Response& res) {
    auto [job, f] = job_frame(req);
    const std::string kind = req.get_param_value("kind");
    const int w = f->width, h = f->height;
    std::vector<uint8_t> rgb;
    double scale = 0;
    if (kind == "render" || kind.empty()) {
      rgb = to_png_bytes(f->image());
    } else if (kind == "rate") {
      // The course's rate image: samples taken / -s.
      const int target = std::max(1, job->opts.samples_per_pixel);
      rgb = flip_to_rgb(w, h, [&](size_t i, uint8_t out[3]) {
        uint32_t n;
        std::memcpy(&n, &f->payload[i * 20 + 12], 4);
        rate_to_rgb(float(n) / float(f->samples > 0 ? f->samples : target), out);
      });
    } else if (kind == "tests") {
      for (size_t i = 0; i < size_t(w) * h; ++i) scale = std::max(scale, double(f->tests(i)));
      rgb = flip_to_rgb(w, h, [&](size_t i, uint8_t out[3]) {
        rate_to_rgb(scale > 0 ? float(f->tests(i) / scale) : 0.0f, out);
      });
    } else {
      throw BadRequest("kind: expected render, rate or tests");
    }
    res.set_content(std::string(rgb.begin(), rgb.end()), "application/octet-stream");
    res.set_header("X-Width", std::to_string(w));
    res.set_header("X-Height", std::to_string(h));
    res.set_header("X-Pass", std::to_string(f->pass));
    res.set_header("X-Samples", std::to_string(f->samples));
    res.set_header("X-Scale", num(scale));
    res.set_header("Cache-Control", "no-store");
  }));
  // The grader's comparison of the job's image with a case's reference:
  // |z| per pixel (black to white at the threshold, red beyond), as RGB
  // rows from the top, and the grader's summary in X-Summary.
  svr.Get("/api/diff", guarded([&](const httplib::Request& req, httplib::Response& res) {
    auto [job, f] = job_frame(req);
    const std::string name = req.get_param_value("case");
    const ViewerCase* vc = nullptr;
    for (const ViewerCase& x : app.cases)
      if (x.c.name == name) vc = &x;
    if (!vc) throw BadRequest("case: no grading case named '" + name + "'", 404);
    RenderOptions shown = job->opts;
    shown.samples_per_pixel = f->samples;
    if (image_key(shown) != image_key(vc->opts) || job->opts.cell_set)
      throw BadRequest("this render's settings are not case " + name + "'s: apply the case's settings first", 409);
    grader::Reference ref;
    std::string why;
    if (!grader::load_reference(c.source_dir + "/reference_images", vc->c, &ref, &why))
      throw BadRequest(name + ": " + why, 404);
    const int w = f->width, h = f->height;
    if (ref.mean.width != w || ref.mean.height != h) throw BadRequest(name + ": the reference is another size", 409);
    const ImageBuffer mine = f->image();
    int fx = 0, fy = 0;
    if (const int bad = grader::count_non_finite(mine, &fx, &fy))
      throw BadRequest(std::to_string(bad) + " pixels are NaN or infinite", 422);
    const grader::ImageScore sc =
        grader::score_image(mine, ref.mean, ref.variance, ref.runs, grader::case_score_options(vc->c, ref));
    // Deterministic references measure |c - m| in tolerances: 1 is the limit.
    const double threshold = sc.deterministic ? 1.0 : sc.pixel_threshold;
    const grader::Picture pic = grader::error_picture(sc.pixel_z, w, h, threshold);
    res.set_content(std::string(pic.rgb.begin(), pic.rgb.end()), "application/octet-stream");
    res.set_header("X-Width", std::to_string(w));
    res.set_header("X-Height", std::to_string(h));
    res.set_header("X-Pass", std::to_string(f->pass));
    res.set_header("X-Scale", num(threshold));
    res.set_header("X-Summary", (sc.passed ? "matches the reference: " : "differs from the reference: ") + sc.summary());
  }));
  svr.Get("/api/png", guarded([&](const httplib::Request& req, httplib::Response& res) {
    auto [job, f] = job_frame(req);
    const std::vector<uint8_t> png = encode_png(f->image());
    res.set_content(std::string(png.begin(), png.end()), "image/png");
    res.set_header("Content-Disposition", "attachment; filename=\"render.png\"");
  }));
  svr.Get("/api/pfm", guarded([&](const httplib::Request& req, httplib::Response& res) {
    auto [job, f] = job_frame(req);
    const std::vector<uint8_t> pfm = encode_pfm(f->image());
    res.set_content(std::string(pfm.begin(), pfm.end()), "application/octet-stream");
    res.set_header("Content-Disposition", "attachment; filename=\"render.pfm\"");
  }));
  // The BVH job's result: uint32 length of the JSON head, the head, then
  // the payload of worker.cpp's run_bvh.
  svr.Get("/api/bvh-data", guarded([&](const httplib::Request& req, httplib::Response& res) {
    auto job = find_job(req);
    std::lock_guard<std::mutex> lock(job->mu);
    if (!job->bvh) throw BadRequest("no BVH yet", 404);
    const uint32_t n = uint32_t(job->bvh_head.size());
    std::string body(4, '\0');
    std::memcpy(body.data(), &n, 4);
    body += job->bvh_head;
    body.append(reinterpret_cast<const char*>(job->bvh->data()), job->bvh->size());
    res.set_content(body, "application/octet-stream");
  }));

  const int port = c.port > 0 ? (svr.bind_to_port("127.0.0.1", c.port) ? c.port : -1)
                              : svr.bind_to_any_port("127.0.0.1");
  if (port <= 0) {
    std::fprintf(stderr, "viewer: error: cannot listen on 127.0.0.1:%d (in use?)\n", c.port);
    return 1;
  }
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  std::signal(SIGPIPE, SIG_IGN);
  std::printf("http://127.0.0.1:%d/?token=%s\n", port, c.token.c_str());
  std::fflush(stdout);
  std::fprintf(stderr, "viewer: serving %s; Ctrl-C stops\n", c.start.scene_path.c_str());
  // A render nobody watches (the page was closed) is stopped after 30 s.
  std::mutex watch_mu;
  std::condition_variable watch_cv;
  bool watching = true;
  std::thread watchdog([&] {
    std::unique_lock<std::mutex> lock(watch_mu);
    while (!watch_cv.wait_for(lock, std::chrono::seconds(5), [&] { return !watching; }))
      app.workers.stop_unwatched(30.0);
  });
  svr.listen_after_bind();
  {
    std::lock_guard<std::mutex> lock(watch_mu);
    watching = false;
  }
  watch_cv.notify_all();
  watchdog.join();
  app.workers.stop_all();
  std::error_code ec;
  fs::remove_all(app.temp_dir, ec);
  return 0;
}

}  // namespace pt::viewer
