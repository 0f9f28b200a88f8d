// viewer: the student's window on this build, a local web app.
//   viewer [--port N] [--allow DIR]... [--idle-stop S] [pathtracer flags] scene.dae
// prints one URL and serves until Ctrl-C. The render flags set the page's
// starting settings; the page may open scene, camera and environment files
// in the folders of the files named here and in the --allow folders.
#include <unistd.h>

#include <climits>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "common/todo.h"
#include "pathtracer/options.h"
#include "viewer/server.h"
#include "viewer/worker.h"

namespace {

std::string self_exe(const char* argv0) {
  char buf[PATH_MAX];
  const ssize_t n = ::readlink("/proc/self/exe", buf, sizeof buf - 1);
  if (n > 0) return std::string(buf, size_t(n));
  return argv0;
}

// The parts of this build that still have stubs (PT_TODO lines, compiled
// in whether they run or not).
std::set<int> stub_parts() {
  std::set<int> parts;
  for (const pt::TodoSite& s : pt::todo_sites()) parts.insert(s.part);
#ifdef PT_VIEWER_PLANTS
  // Test builds: PT_VIEWER_PLANT=stubs pretends parts 2 to 5 are stubs.
  if (const char* p = std::getenv("PT_VIEWER_PLANT"); p && std::string(p) == "stubs") parts.insert({2, 3, 4, 5});
#endif
  return parts;
}

// Starts at the last part whose functions are all written (part 1 when
// part 1's are not), and says why in one line.
void start_at_written_part(pt::viewer::ServerConfig* cfg) {
  const std::set<int> stubs = stub_parts();
  if (stubs.empty()) return;
  const int first = *stubs.begin();
  std::string missing;
  for (int p : stubs) missing += (missing.empty() ? "" : ", ") + std::to_string(p);
  const std::string which = (stubs.size() == 1 ? "part " : "parts ") + missing;
  if (first <= 1) {
    cfg->start.part = 1;
    cfg->start_note = "Starting at part 1: its functions are not written yet (" + which +
                      " still have TODO stubs; the banner lists part 1's).";
  } else {
    cfg->start.part = first - 1;
    cfg->start_note = "Starting at part " + std::to_string(first - 1) + ", the last part written: " + which +
                      (stubs.size() == 1 ? " still has" : " still have") +
                      " TODO stubs. Pick a part under \"part\" to see another.";
  }
}

std::string parent_folder(const std::string& file) {
  const std::filesystem::path p = std::filesystem::absolute(file).parent_path();
  return p.empty() ? "." : p.string();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 2 && std::strcmp(argv[1], "--worker") == 0) return pt::viewer::worker_main(argc, argv);
  try {
    pt::viewer::ServerConfig cfg;
    std::vector<std::string> allow;
    std::vector<char*> rest = {argv[0]};
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      if ((a == "--port" || a == "--allow" || a == "--idle-stop") && i + 1 < argc) {
        const std::string v = argv[++i];
        if (a == "--allow") {
          allow.push_back(v);
          continue;
        }
        if (a == "--idle-stop") {
          char* end = nullptr;
          const double s = std::strtod(v.c_str(), &end);
          if (v.empty() || *end != '\0' || !(s >= 0.1 && s <= 86400)) {
            std::fprintf(stderr, "viewer: error: --idle-stop: expected seconds from 0.1 to 86400, got '%s'\n", v.c_str());
            return 2;
          }
          cfg.idle_stop_seconds = s;
          continue;
        }
        if (v.empty() || v.size() > 5 || v.find_first_not_of("0123456789") != std::string::npos ||
            std::stoi(v) > 65535) {
          std::fprintf(stderr, "viewer: error: --port: expected a port number from 0 to 65535, got '%s'\n", v.c_str());
          return 2;
        }
        cfg.port = std::stoi(v);
      } else if (a == "--port" || a == "--allow" || a == "--idle-stop") {
        std::fprintf(stderr, "viewer: error: %s needs a value\n", a.c_str());
        return 2;
      } else if (a == "-h" || a == "--help") {
        std::printf(
            "viewer: watch this build render and walk its BVH, in the browser.\n"
            "Usage: viewer [--port N] [--allow DIR]... [--idle-stop S] [pathtracer flags] scene.dae\n"
            "Prints one URL (with its access token) and serves on 127.0.0.1 until Ctrl-C.\n"
            "  --port N     listen on port N (default: any free port)\n"
            "  --allow DIR  let the page open scene, camera (-c) and environment (-e) files in DIR too\n"
            "               (the folders of the files named on the command line are always allowed)\n"
            "  --idle-stop S  stop a render or Debug call no page has asked about for S seconds (default 30)\n"
            "The pathtracer flags (-s -l -m -o -H -t -a -b -d -r -c -e --part --seed ...) set the starting\n"
            "settings; see 'pathtracer -h'. viewer/README.md describes the page.\n");
        return 0;
      } else {
        rest.push_back(argv[i]);
      }
    }
    if (auto code = pt::parse_command_line(int(rest.size()), rest.data(), &cfg.start)) return *code;
    cfg.start.progress = false;
    // Without --part: the last part whose code is written.
    bool part_given = false;
    for (char* a : rest) part_given = part_given || std::strcmp(a, "--part") == 0;
    if (!part_given) start_at_written_part(&cfg);
    cfg.files.allow_folder(parent_folder(cfg.start.scene_path));
    if (!cfg.start.camera_settings.empty()) cfg.files.allow_folder(parent_folder(cfg.start.camera_settings));
    if (!cfg.start.env_map.empty()) cfg.files.allow_folder(parent_folder(cfg.start.env_map));
    for (const std::string& d : allow) cfg.files.allow_folder(d);
    // The starting files, resolved, so that the page names them as it
    // names every file it lists.
    std::string why;
    const std::string scene = cfg.files.resolve(cfg.start.scene_path, pt::viewer::FileKind::Scene, &why);
    if (scene.empty()) {
      std::fprintf(stderr, "viewer: error: %s\n", why.c_str());
      return 1;
    }
    cfg.start.scene_path = scene;
    if (!cfg.start.camera_settings.empty()) {
      cfg.start.camera_settings =
          cfg.files.resolve(cfg.start.camera_settings, pt::viewer::FileKind::Camera, &why);
      if (cfg.start.camera_settings.empty()) {
        std::fprintf(stderr, "viewer: error: -c %s\n", why.c_str());
        return 1;
      }
    }
    if (!cfg.start.env_map.empty()) {
      cfg.start.env_map = cfg.files.resolve(cfg.start.env_map, pt::viewer::FileKind::Environment, &why);
      if (cfg.start.env_map.empty()) {
        std::fprintf(stderr, "viewer: error: -e %s\n", why.c_str());
        return 1;
      }
    }
    cfg.worker_exe = self_exe(argv[0]);
    cfg.web_dir = PT_VIEWER_WEB_DIR;
    cfg.source_dir = PT_SOURCE_DIR;
    return pt::viewer::run_server(std::move(cfg));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "viewer: error: %s\n", e.what());
    return 1;
  }
}
