// The server: its setup (the token, the temporary folder, the watchdog
// that stops an unwatched render) and its routes, grouped by what they
// serve: the page, the scene, renders, the BVH.
#include "viewer/server.h"

#include <malloc.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <random>
#include <sstream>
#include <thread>
#include <vector>

#include <httplib.h>

#include "viewer/access.h"
#include "viewer/camera_file.h"
#include "viewer/http_helpers.h"
#include "common/image_io.h"
#include "common/json.h"
#include "viewer/overlays.h"
#include "pathtracer/render_job.h"
#include "viewer/requests.h"
#include "viewer/routes.h"

namespace pt::viewer {

namespace fs = std::filesystem;

namespace {

std::string num(double v) { return pt::json_number(v); }

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

std::string three_dir(const ServerConfig& c) { return c.web_dir + "/node_modules/three"; }

std::string files_json(const FileAccess& files, FileKind kind) {
  std::string s = "[";
  for (const std::string& f : files.list(kind)) s += (s.size() > 1 ? "," : "") + json_quote(f);
  return s + "]";
}

void serve_file(httplib::Response& res, const std::string& path, const char* type) {
  std::string body;
  if (!read_file(path, &body)) {
    send_error(res, path + ": missing (run scripts/setup.sh)", 404);
    return;
  }
  res.set_content(body, type);
  res.set_header("Cache-Control", "no-cache");
}

// /api/state: the starting settings, the files the page may open, the
// cases it may use, and whether three.js is there.
std::string state_json(const App& app) {
  const ServerConfig& c = app.cfg;
  std::ostringstream s;
  s << "{\"start\":" << settings_json(c.start) << ",\"start_note\":" << json_quote(c.start_note)
    << ",\"parts_built\":" << kPartsBuilt
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
  s << "],\"three\":" << (fs::exists(three_dir(c) + "/build/three.module.js") ? "true" : "false") << "}";
  return s.str();
}

// The request's scene, read by the server (422 when it cannot be read).
std::shared_ptr<const Scene> request_scene(App& app, const Request& q) {
  try {
    return app.scenes.get(q.opts.scene_path);
  } catch (const std::exception& e) {
    throw BadRequest(e.what(), 422);
  }
}

// The camera of the request's render (422 when the scene or the camera
// file cannot be read).
Camera checked_camera(const Scene& scene, const Request& q) {
  try {
    return request_camera(scene, q);
  } catch (const std::exception& e) {
    throw BadRequest(e.what(), 422);
  }
}

// The frame's image headers the page reads.
void set_image_headers(httplib::Response& res, const Frame& f) {
  res.set_header("X-Width", std::to_string(f.width));
  res.set_header("X-Height", std::to_string(f.height));
  res.set_header("X-Pass", std::to_string(f.pass));
}

// Sends `bytes` as they are: the response keeps them until it is written.
void send_bytes(httplib::Response& res, std::vector<uint8_t> bytes, const char* type) {
  auto kept = std::make_shared<const std::vector<uint8_t>>(std::move(bytes));
  res.set_content_provider(kept->size(), type, [kept](size_t offset, size_t length, httplib::DataSink& sink) {
    return sink.write(reinterpret_cast<const char*>(kept->data()) + offset, std::min<size_t>(length, 1 << 20));
  });
}

// Refuses what access.h refuses (a JSON error under /api/, a line of text
// elsewhere) and answers errors without a body with a JSON one. `port` is
// the port the server listens on, known once it is bound.
void add_access_check(httplib::Server& svr, const std::string& token, const int& port) {
  svr.set_pre_routing_handler([&token, &port](const httplib::Request& req, httplib::Response& res) {
    const Refusal r = check_request(req, token, port);
    if (r.status == 0) return httplib::Server::HandlerResponse::Unhandled;
    if (req.path.rfind("/api/", 0) == 0)
      send_error(res, r.reason, r.status);
    else
      res.set_content(r.reason + "\n", "text/plain; charset=utf-8");
    res.status = r.status;
    return httplib::Server::HandlerResponse::Handled;
  });
  svr.set_error_handler([](const httplib::Request&, httplib::Response& res) {
    if (res.body.empty()) res.set_content("{\"error\":\"HTTP " + std::to_string(res.status) + "\"}", "application/json");
  });
}

// Serves until stopped; a job nobody watches (its page was closed) is
// stopped after cfg.idle_stop_seconds.
void serve(httplib::Server& svr, App& app) {
  std::mutex watch_mu;
  std::condition_variable watch_cv;
  bool watching = true;
  const double idle = app.cfg.idle_stop_seconds;
  std::thread watchdog([&] {
    std::unique_lock<std::mutex> lock(watch_mu);
    const auto period = std::chrono::duration<double>(std::min(5.0, std::max(0.1, idle / 2)));
    while (!watch_cv.wait_for(lock, period, [&] { return !watching; }))
      for (const auto& job : app.workers.stop_unwatched(idle))
        std::fprintf(stderr, "viewer: stopped job %llu (%s): no page asked about it for %g s\n",
                     (unsigned long long)job->id, job->kind.c_str(), idle);
  });
  svr.listen_after_bind();
  {
    std::lock_guard<std::mutex> lock(watch_mu);
    watching = false;
  }
  watch_cv.notify_all();
  watchdog.join();
}

}  // namespace

bool server_stopping() { return g_stop; }

std::string random_token() {
  std::random_device rd;  // /dev/urandom
  std::string t;
  const char* hex = "0123456789abcdef";
  for (int i = 0; i < 32; ++i) t += hex[rd() & 15];
  return t;
}

// ------------------------------------------------------------------ jobs

std::shared_ptr<Job> launch_job(App& app, const std::string& kind, const Json& body,
                                const std::vector<std::string>& pre) {
  const ServerConfig& c = app.cfg;
  Request q = read_request(body, c.start, c.files);
  if (kind == "normals") {
    q.opts.part = std::min(q.opts.part, 2);
    q.opts.samples_per_pixel = 1;
    q.opts.cell_set = false;
  }
  if (q.camera.set) {
    // The page's view becomes a -c file, read the way the command line
    // reads one (the file "save camera" downloads).
    const Camera cam = checked_camera(*request_scene(app, q), q);
    const std::string path = app.temp_dir + "/camera_" + std::to_string(++app.camera_files) + ".txt";
    std::ofstream(path) << camera_settings_text(cam);
    q.opts.camera_settings = path;
  }
  std::vector<std::string> flags = pre;
  for (const std::string& f : render_flags(q.opts)) flags.push_back(f);
  return app.workers.start(kind, q.opts, flags);
}

void start_job(App& app, const std::string& kind, const httplib::Request& req, httplib::Response& res) {
  auto job = launch_job(app, kind, body_json(req), {});
  std::lock_guard<std::mutex> lock(job->mu);
  send_json(res, job_json(*job));
}

std::shared_ptr<Job> find_job(App& app, const httplib::Request& req) {
  auto job = app.workers.find(param_u64(req, "job"));
  if (!job) throw BadRequest("no such job (it may have been replaced by newer ones)", 404);
  return job;
}

std::pair<std::shared_ptr<Job>, std::shared_ptr<const Frame>> job_frame(App& app, const httplib::Request& req) {
  auto job = find_job(app, req);
  std::lock_guard<std::mutex> lock(job->mu);
  if (!job->frame) throw BadRequest("no frame yet", 404);
  return std::make_pair(job, job->frame);
}

// ---------------------------------------------------------------- routes

// The page (index.html sets the token's cookie), its modules, three.js,
// and /api/state.
void add_page_routes(httplib::Server& svr, App& app) {
  const ServerConfig& c = app.cfg;
  svr.Get("/", [&c, &app](const httplib::Request&, httplib::Response& res) {
    serve_file(res, c.web_dir + "/index.html", "text/html; charset=utf-8");
    res.set_header("Set-Cookie", cookie_name(app.port) + "=" + c.token + "; Path=/; HttpOnly; SameSite=Strict");
  });
  svr.Get(R"(/web/([a-z0-9_]+)\.(js|css))", [&c](const httplib::Request& req, httplib::Response& res) {
    const std::string ext = req.matches[2];
    serve_file(res, c.web_dir + "/" + std::string(req.matches[1]) + "." + ext,
               ext == "js" ? kJavaScript : "text/css; charset=utf-8");
  });
  svr.Get("/three/three.module.js", [&c](const httplib::Request&, httplib::Response& res) {
    serve_file(res, three_dir(c) + "/build/three.module.js", kJavaScript);
  });
  svr.Get("/api/state", guarded([&app](const httplib::Request&, httplib::Response& res) {
    send_json(res, state_json(app));
  }));
}

// The scene as the page draws it: camera (with the settings applied),
// bounds, counts; /api/mesh gives its triangles and spheres (scenes.h);
// /api/camera-file the course's camera settings file for the page's view.
void add_scene_routes(httplib::Server& svr, App& app) {
  svr.Post("/api/scene", guarded([&app](const httplib::Request& req, httplib::Response& res) {
    const Request q = read_request(body_json(req), app.cfg.start, app.cfg.files);
    const std::shared_ptr<const Scene> scene = request_scene(app, q);
    const Camera cam = checked_camera(*scene, q);
    const BBox b = scene->bounds();
    std::ostringstream s;
    s << "{\"scene\":" << json_quote(q.opts.scene_path) << ",\"camera\":" << camera_json(cam)
      << ",\"default_camera\":" << camera_json(default_camera(*scene, q.opts))
      << ",\"bounds\":{\"lo\":" << vec_json(Vec3d(b.lo)) << ",\"hi\":" << vec_json(Vec3d(b.hi)) << "}"
      << ",\"triangles\":" << scene->triangles.size() << ",\"spheres\":" << scene->spheres.size()
      << ",\"lights\":" << scene->lights.size() << "}";
    send_json(res, s.str());
  }));
  svr.Post("/api/mesh", guarded([&app](const httplib::Request& req, httplib::Response& res) {
    const Request q = read_request(body_json(req), app.cfg.start, app.cfg.files);
    res.set_content(mesh_bytes(*request_scene(app, q)), "application/octet-stream");
  }));
  svr.Post("/api/camera-file", guarded([&app](const httplib::Request& req, httplib::Response& res) {
    const Request q = read_request(body_json(req), app.cfg.start, app.cfg.files);
    const Camera cam = checked_camera(*request_scene(app, q), q);
    res.set_content(camera_settings_text(cam), "text/plain");
    res.set_header("Content-Disposition", "attachment; filename=\"camera.txt\"");
  }));
}

// Renders: start (render, normals), stop, the long-polled status, and the
// latest frame as an image, an overlay, a difference, a PNG or a PFM.
void add_render_routes(httplib::Server& svr, App& app) {
  svr.Post("/api/render", guarded([&app](const httplib::Request& req, httplib::Response& res) {
    start_job(app, "render", req, res);
  }));
  svr.Post("/api/normals", guarded([&app](const httplib::Request& req, httplib::Response& res) {
    start_job(app, "normals", req, res);
  }));
  // Stops the render (or the job of {"job": id}) and answers once its
  // worker is gone.
  svr.Post("/api/stop", guarded([&app](const httplib::Request& req, httplib::Response& res) {
    const Json body = req.body.empty() ? json_object() : body_json(req);
    if (body.type == Json::Type::Object && body.get("job")) {
      const double id = body.num("job", -1);
      auto job = id >= 0 ? app.workers.find(uint64_t(id)) : nullptr;
      if (!job) throw BadRequest("no such job (it may have been replaced by newer ones)", 404);
      app.workers.stop(job, "stopped");
    } else {
      app.workers.stop_kind("render", "stopped");
    }
    send_json(res, "{}");
  }));
  // Waits (up to 10 s) until the job has more than `after` frames or has
  // ended. A waiting request holds one of the server's threads: beyond
  // kMaxWaitingPolls of them (many tabs, or a program flooding it) the
  // status is answered at once with "busy", so that the other requests
  // always find a thread.
  svr.Get("/api/status", guarded([&app](const httplib::Request& req, httplib::Response& res) {
    auto job = find_job(app, req);
    const long long after = req.has_param("after") ? (long long)param_u64(req, "after") : -1;
    if (app.waiting_polls.fetch_add(1) >= kMaxWaitingPolls) {
      --app.waiting_polls;
      std::lock_guard<std::mutex> lock(job->mu);
      job->last_seen = now_seconds();
      std::string s = job_json(*job);
      s.insert(1, "\"busy\":true,");
      return send_json(res, s);
    }
    struct Leave {
      std::atomic<int>& n;
      ~Leave() { --n; }
    } leave{app.waiting_polls};
    std::unique_lock<std::mutex> lock(job->mu);
    job->last_seen = now_seconds();
    ++job->waiting_polls;  // a page waiting on it is watching it
    job->cv.wait_for(lock, std::chrono::seconds(10),
                     [&] { return job->state != "running" || job->frames > after || g_stop; });
    --job->waiting_polls;
    job->last_seen = now_seconds();
    send_json(res, job_json(*job));
  }));
  // Images are converted one at a time (App::converting); a PFM is
  // streamed from the frame.
  svr.Get("/api/image", guarded([&app](const httplib::Request& req, httplib::Response& res) {
    auto [job, f] = job_frame(app, req);
    std::unique_lock<std::mutex> one(app.converting);
    Overlay o = frame_overlay(*f, req.get_param_value("kind"), job->opts.samples_per_pixel);
    one.unlock();
    send_bytes(res, std::move(o.rgb), "application/octet-stream");
    set_image_headers(res, *f);
    res.set_header("X-Samples", std::to_string(f->samples));
    res.set_header("X-Scale", num(o.scale));
    res.set_header("Cache-Control", "no-store");
  }));
  // The grader's comparison of the job's image with a case's reference
  // (overlays.h), the grader's summary in X-Summary and the likely causes
  // (hints_json) in X-Hints.
  svr.Get("/api/diff", guarded([&app](const httplib::Request& req, httplib::Response& res) {
    auto [job, f] = job_frame(app, req);
    const std::string name = req.get_param_value("case");
    const ViewerCase* vc = find_case(app.cases, name);
    if (!vc) throw BadRequest("case: no grading case named '" + name + "'", 404);
    // An earlier pass of the case's render: not an error, the difference
    // comes with the last pass (202 and when); a render stopped before it
    // never gets there.
    if (const std::string pending = difference_pending(*f, job->opts, *vc); !pending.empty()) {
      std::lock_guard<std::mutex> lock(job->mu);
      if (job->state != "running")
        throw BadRequest("the render " + job->state + " at " + std::to_string(f->samples) + " samples: render again to " +
                             "compare it with case " + name, 409);
      return send_json(res, "{\"pending\":" + json_quote(pending) + "}", 202);
    }
    std::unique_lock<std::mutex> one(app.converting);
    Difference d = difference_overlay(*f, job->opts, *vc, app.cfg.source_dir + "/reference_images", app.catalogue,
                                      app.case_groups);
    one.unlock();
    send_bytes(res, std::move(d.picture.rgb), "application/octet-stream");
    set_image_headers(res, *f);
    res.set_header("X-Scale", num(d.picture.scale));
    res.set_header("X-Summary", d.verdict);
    res.set_header("X-Hints", hints_json(d));
  }));
  svr.Get("/api/png", guarded([&app](const httplib::Request& req, httplib::Response& res) {
    auto [job, f] = job_frame(app, req);
    std::unique_lock<std::mutex> one(app.converting);
    std::vector<uint8_t> png = frame_png(*f);
    one.unlock();
    send_bytes(res, std::move(png), "image/png");
    res.set_header("Content-Disposition", "attachment; filename=\"render.png\"");
  }));
  svr.Get("/api/pfm", guarded([&app](const httplib::Request& req, httplib::Response& res) {
    auto [job, f] = job_frame(app, req);
    const std::shared_ptr<const Frame> frame = f;
    res.set_content_provider(frame_pfm_size(*frame), "application/octet-stream",
                             [frame](size_t offset, size_t length, httplib::DataSink& sink) {
                               std::vector<char> chunk(std::min<size_t>(length, 1 << 16));
                               frame_pfm_bytes(*frame, offset, chunk.size(), chunk.data());
                               return sink.write(chunk.data(), chunk.size());
                             });
    res.set_header("Content-Disposition", "attachment; filename=\"render.pfm\"");
  }));
}

// The BVH: start a build, and its result: uint32 length of the JSON head,
// the head, then the payload of worker.cpp's run_bvh.
void add_bvh_routes(httplib::Server& svr, App& app) {
  svr.Post("/api/bvh", guarded([&app](const httplib::Request& req, httplib::Response& res) {
    start_job(app, "bvh", req, res);
  }));
  svr.Get("/api/bvh-data", guarded([&app](const httplib::Request& req, httplib::Response& res) {
    auto job = find_job(app, req);
    std::lock_guard<std::mutex> lock(job->mu);
    if (!job->bvh) throw BadRequest("no BVH yet", 404);
    const uint32_t n = uint32_t(job->bvh_head.size());
    std::string body(4, '\0');
    std::memcpy(body.data(), &n, 4);
    body += job->bvh_head;
    body.append(reinterpret_cast<const char*>(job->bvh->data()), job->bvh->size());
    res.set_content(body, "application/octet-stream");
  }));
}

// ------------------------------------------------------------------ server

int run_server(ServerConfig cfg) {
  if (cfg.token.empty()) cfg.token = random_token();
  App app(std::move(cfg));
  const ServerConfig& c = app.cfg;
  app.cases = load_cases(c.source_dir, c.files);
  app.catalogue = load_catalogue(c.source_dir);
  {
    std::vector<grader::Case> cases;
    for (const ViewerCase& vc : app.cases) cases.push_back(vc.c);
    app.case_groups = grader::case_groups(cases);
  }
  {
    char tmpl[] = "/tmp/pt-viewer-XXXXXX";
    if (!::mkdtemp(tmpl)) {
      std::fprintf(stderr, "viewer: error: cannot create a temporary folder\n");
      return 1;
    }
    app.temp_dir = tmpl;
  }
  if (!fs::exists(three_dir(c) + "/build/three.module.js"))
    std::fprintf(stderr,
                 "viewer: warning: %s is missing: the 3D views need it (run scripts/setup.sh, which runs npm ci "
                 "in viewer/web)\n",
                 three_dir(c).c_str());

  // Frames are large (20 bytes a pixel): allocations of a megabyte or more
  // are mapped on their own and given back to the system when freed,
  // whatever sizes came before (glibc otherwise raises this threshold to
  // the largest block freed, and keeps such blocks in its heap).
  mallopt(M_MMAP_THRESHOLD, 1 << 20);
  httplib::Server svr;
  g_server = &svr;
  svr.set_payload_max_length(1 << 16);
  // A browser keeps several connections open and the page long-polls on
  // one: enough threads that an idle kept-alive connection never starves
  // a request (routes.h), and idle connections let go soon.
  svr.new_task_queue = [] { return new httplib::ThreadPool(kServerThreads); };
  svr.set_keep_alive_timeout(2);
  // httplib's default sets SO_REUSEPORT, with which a second viewer on the
  // same port binds too and the kernel shares the connections between
  // them. SO_REUSEADDR alone lets a restarted viewer take its port back
  // from connections still closing, but not from a listening server.
  svr.set_socket_options([](socket_t sock) {
    int yes = 1;
    ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  add_access_check(svr, c.token, app.port);
  add_page_routes(svr, app);
  add_scene_routes(svr, app);
  add_render_routes(svr, app);
  add_bvh_routes(svr, app);
  add_debug_routes(svr, app);

  const int port = c.port > 0 ? (svr.bind_to_port("127.0.0.1", c.port) ? c.port : -1)
                              : svr.bind_to_any_port("127.0.0.1");
  app.port = port;
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
  serve(svr, app);
  app.workers.stop_all();
  std::error_code ec;
  fs::remove_all(app.temp_dir, ec);
  return 0;
}

}  // namespace pt::viewer
