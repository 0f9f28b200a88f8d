// The server's state, shared by its routes, and what a route that starts
// or reads a job needs. server.cpp registers the routes (add_*_routes);
// a file of new routes declares its own add_ function here and is
// registered in run_server.
#pragma once
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include <httplib.h>

#include "viewer/scenes.h"
#include "viewer/server.h"
#include "viewer/viewer_cases.h"
#include "viewer/workers.h"

namespace pt::viewer {

// The server's threads, and how many of them status requests may hold
// waiting for a job's next frame: the rest serve everything else (a
// browser keeps a few connections open, each on a thread while it lasts).
constexpr int kServerThreads = 32;
constexpr int kMaxWaitingPolls = 16;

struct App {
  ServerConfig cfg;
  Workers workers;
  SceneCache scenes;
  std::string temp_dir;
  std::atomic<uint64_t> camera_files{0};
  std::vector<ViewerCase> cases;
  grader::Catalogue catalogue;  // the known bugs, for the difference's likely causes
  grader::CaseGroups case_groups;
  int port = 0;  // the port it listens on, once bound
  std::atomic<int> waiting_polls{0};  // status requests waiting now
  // Held while a frame is converted into an image for the page or a PNG,
  // so that requests at once never hold more than one conversion's memory.
  std::mutex converting;

  explicit App(ServerConfig c) : cfg(std::move(c)), workers(cfg.worker_exe, cfg.source_dir) {}
};

// Starts a job of `kind` ("render", "normals" or "bvh") for the request's
// settings (cancelling the running one of that kind) and replies with its
// status.
void start_job(App& app, const std::string& kind, const httplib::Request& req, httplib::Response& res);

// Starts a worker job of `kind` for the page's settings `body`; `pre` goes
// before the flags (a debug job's tool and input).
std::shared_ptr<Job> launch_job(App& app, const std::string& kind, const Json& body,
                                const std::vector<std::string>& pre);

// The job of the request's ?job= (404 when it is gone).
std::shared_ptr<Job> find_job(App& app, const httplib::Request& req);

// That job and its latest frame (404 when it has none yet).
std::pair<std::shared_ptr<Job>, std::shared_ptr<const Frame>> job_frame(App& app, const httplib::Request& req);

// Whether the server is stopping (SIGINT or SIGTERM): long polls return.
bool server_stopping();

void add_page_routes(httplib::Server& svr, App& app);
void add_scene_routes(httplib::Server& svr, App& app);
void add_render_routes(httplib::Server& svr, App& app);
void add_bvh_routes(httplib::Server& svr, App& app);
// Debug mode (debug_routes.cpp).
void add_debug_routes(httplib::Server& svr, App& app);

}  // namespace pt::viewer
