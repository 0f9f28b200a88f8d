// The server's side of the worker processes (worker.h): a job is one
// worker, started from this binary with the flags of its render; its
// messages (frames, a BVH, TODO lines, a crash's backtrace) are read as
// they come, and how it ended becomes the job's state and message.
#pragma once
#include <sys/types.h>

#include <condition_variable>
#include <cstdint>
#include <cstring>
#include <map>
#include <set>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "common/image.h"
#include "common/json.h"
#include "pathtracer/options.h"
#include "viewer/symbols.h"

namespace pt::viewer {

// One pass of a render as the worker sent it.
struct Frame {
  std::string kind;  // "render"
  Json head;
  int width = 0, height = 0, samples = 0, pass = 0;
  std::vector<uint8_t> payload;  // 20 bytes per pixel (worker.h)

  size_t pixels() const { return size_t(width) * size_t(height); }
  Color color(size_t i) const {
    Color c;
    std::memcpy(&c, &payload[i * 20], 12);
    return c;
  }
  uint32_t samples_taken(size_t i) const {
    uint32_t n;
    std::memcpy(&n, &payload[i * 20 + 12], 4);
    return n;
  }
  float tests(size_t i) const {
    float t;
    std::memcpy(&t, &payload[i * 20 + 16], 4);
    return t;
  }
  // A copy as an image (16 bytes a pixel: for the small images of grading
  // cases; the large ones are converted from the payload directly).
  ImageBuffer image() const {
    ImageBuffer img(width, height);
    for (size_t i = 0; i < img.pixels.size(); ++i) {
      img.pixels[i] = color(i);
      img.samples[i] = samples_taken(i);
    }
    return img;
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
  int result_status = 0;              // a debug job's answer: HTTP status and JSON
  std::string result;
  std::shared_ptr<const std::vector<uint8_t>> bvh;
  bool cancel_requested = false;
  std::string cancel_reason;  // "replaced by a newer job", "stopped", ...
  int waiting_polls = 0;  // status requests waiting on it now
  std::string crash_signal;             // the worker's crash report (worker_watch.h)
  std::vector<ThreadPlace> crash_place;
  // The worker's last stall report: no progress for `stall_seconds` (at
  // `stall_at`), in `stall_function` (at `stall_where`, with debug
  // information); 0 when it is moving.
  double stall_seconds = 0, stall_at = 0;
  std::string stall_function, stall_where;
  double started = 0;
  double last_seen = 0;  // the last status request for it
};

// Seconds on a steady clock.
double now_seconds();

// The jobs: at most one worker of each kind alive at any moment, the last
// few jobs kept for the page.
class Workers {
 public:
  // `exe` is the worker's program (this one); `source_dir` the project's
  // folder, from which reports name files.
  Workers(std::string exe, std::string source_dir) : exe_(std::move(exe)), source_dir_(std::move(source_dir)) {}

  // Starts a job of `kind` ("render", "normals", "bvh" or "debug") for
  // `opts` with `flags`. The running job of the same kind is stopped first,
  // and its worker is gone before the new one starts, whatever requests
  // arrive at the same time.
  std::shared_ptr<Job> start(const std::string& kind, const RenderOptions& opts, const std::vector<std::string>& flags);

  std::shared_ptr<Job> find(uint64_t id);
  // Stops every running job of `kind`, or `job`; returns once their
  // workers are gone. `reason` becomes the job's message.
  void stop_kind(const std::string& kind, const std::string& reason);
  void stop(const std::shared_ptr<Job>& job, const std::string& reason);
  // Stops every running job that no page has asked about for `seconds`
  // (no status request waiting, none in that time): a closed tab leaves
  // no worker running. Returns the jobs it stopped.
  std::vector<std::shared_ptr<Job>> stop_unwatched(double seconds);
  void stop_all();
  // How many workers are alive.
  size_t alive();

 private:
  // Files `job` under its id as its kind's latest; returns the job it
  // replaces (cancelled), if any.
  std::shared_ptr<Job> enter(const std::shared_ptr<Job>& job);
  // Kills `jobs`' workers and waits until each is gone.
  void stop_and_wait(const std::vector<std::shared_ptr<Job>>& jobs, const std::string& reason);
  void watch(std::shared_ptr<Job> job, int out_fd, int err_fd);

  std::string exe_, source_dir_;
  std::mutex start_mu_;  // one start at a time, from cancelling the previous job to the new pid
  std::mutex mu_;
  std::condition_variable gone_cv_;
  uint64_t next_id_ = 0;
  std::map<uint64_t, std::shared_ptr<Job>> jobs_;
  std::map<std::string, std::shared_ptr<Job>> latest_;  // by kind
  std::set<std::shared_ptr<Job>> alive_;                // workers started and not yet reaped
};

// Sends the job's worker SIGKILL (its whole process group); a worker
// whose pid is not known yet is killed as soon as it is. `reason` says why
// (the job's message once it has ended).
void cancel(Job& job, const std::string& reason);

// The job as the page's status object. Called with job.mu held.
std::string job_json(Job& job);

}  // namespace pt::viewer
