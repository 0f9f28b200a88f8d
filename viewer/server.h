// The viewer's HTTP server: the page (static files and three.js), a small
// JSON API and image frames, on 127.0.0.1 only, every request carrying the
// random token of the printed URL. Renders and BVH builds run in worker
// processes (worker.h); one render runs at a time.
#pragma once
#include <string>

#include "viewer/file_access.h"
#include "pathtracer/options.h"

namespace pt::viewer {

struct ServerConfig {
  RenderOptions start;       // the command line's settings: the page starts from them
  FileAccess files;          // what the page may open
  std::string worker_exe;    // this program, started as "--worker ..."
  std::string web_dir;       // index.html, the page's modules, node_modules/three
  std::string source_dir;    // the project (reference_images/, grader/cases.txt)
  std::string token;         // empty: a fresh random one
  int port = 0;              // 0: any free port
  double idle_stop_seconds = 30;  // a job no page has asked about for this long is stopped
  std::string start_note;    // why the page starts at the part it starts at (main.cpp), or empty
};

// A random token: 32 hexadecimal digits from the system's random source.
std::string random_token();

// Serves until SIGINT or SIGTERM. Prints the page's URL (with the token)
// as the first line of stdout. Returns the exit status.
int run_server(ServerConfig cfg);

}  // namespace pt::viewer
