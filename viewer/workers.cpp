#include "viewer/workers.h"

#include <cerrno>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <chrono>
#include <cstring>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "viewer/requests.h"

extern char** environ;

namespace pt::viewer {

namespace {

std::string num(double v) { return pt::json_number(v); }

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

// Starts `args` (args[0] the program) in its own process group with
// stdin from /dev/null; its stdout and stderr come back in *out_fd and
// *err_fd. Returns posix_spawn's error (0: started, *pid set).
int spawn_worker(std::vector<std::string> args, pid_t* pid, int* out_fd, int* err_fd) {
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
  const int rc = posix_spawn(pid, args[0].c_str(), &fa, &attr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  posix_spawnattr_destroy(&attr);
  ::close(out[1]);
  ::close(err[1]);
  if (rc != 0) {
    ::close(out[0]);
    ::close(err[0]);
    return rc;
  }
  *out_fd = out[0];
  *err_fd = err[0];
  return 0;
}

// The worker's stderr: TODO lines, a crash report, stall reports, errors,
// and the last lines for the page's log. A stall report is named at once
// (addr2line on `exe`), so that the page can say where the job is stuck.
void read_worker_stderr(const std::shared_ptr<Job>& job, int err_fd, const std::string& exe,
                        const std::string& source_dir) {
  std::string line;
  while (read_line(err_fd, &line)) {
    if (line.rfind("STALL ", 0) == 0) {
      std::istringstream in(line.substr(6));
      double seconds = 0;
      in >> seconds;
      std::string rest, group;
      std::getline(in, rest);
      std::vector<ThreadPlace> threads;
      std::istringstream groups(rest);
      while (std::getline(groups, group, '|')) {
        ThreadPlace t;
        if (parse_thread_place(group, &t)) threads.push_back(t);
      }
      const NamedPlace where = seconds > 0 ? innermost_function(exe, source_dir, threads) : NamedPlace{};
      std::lock_guard<std::mutex> lock(job->mu);
      job->stall_seconds = seconds;
      job->stall_at = now_seconds();
      job->stall_function = where.function;
      job->stall_where = where.where;
      job->cv.notify_all();
      continue;
    }
    std::lock_guard<std::mutex> lock(job->mu);
    if (line.rfind("TODO: implement ", 0) == 0) {
      const std::string what = line.substr(16);
      if (std::find(job->todo.begin(), job->todo.end(), what) == job->todo.end()) job->todo.push_back(what);
      job->cv.notify_all();
    } else if (line.rfind("CRASH ", 0) == 0) {
      // "CRASH SIGSEGV pc=... stack=...": named once the worker is gone.
      const size_t space = line.find(' ', 6);
      job->crash_signal = line.substr(6, space == std::string::npos ? std::string::npos : space - 6);
      ThreadPlace t;
      if (space != std::string::npos && parse_thread_place(line.substr(space + 1), &t)) job->crash_place = {t};
      continue;
    } else if (line.rfind("ERROR ", 0) == 0) {
      if (job->message.empty()) job->message = line.substr(6);
    } else if (line.rfind("pathtracer: error: ", 0) == 0) {
      job->message = line.substr(19);
    }
    job->log.push_back(line);
    if (job->log.size() > 20) job->log.erase(job->log.begin());
  }
  ::close(err_fd);
}

// The worker's stdout: frames and the BVH, until DONE or a message that
// does not parse. Returns whether it said DONE.
bool read_worker_stdout(const std::shared_ptr<Job>& job, int out_fd) {
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
  return done;
}

// How the worker ended (its wait status, whether it said DONE) as the
// job's state and message: a crash names the function it crashed in, and
// its file and line where the build has debug information.
void record_end(Job& job, int status, bool done, const std::string& exe, const std::string& source_dir) {
  std::vector<ThreadPlace> place;
  {
    std::lock_guard<std::mutex> lock(job.mu);
    place = job.crash_place;
  }
  const NamedPlace crashed =
      WIFSIGNALED(status) && !place.empty() ? innermost_function(exe, source_dir, place) : NamedPlace{};
  std::lock_guard<std::mutex> lock(job.mu);
  const std::string doing = job.kind == "bvh" ? "building the BVH" : job.kind == "debug" ? "debugging" : "rendering";
  if (job.cancel_requested) {
    job.state = "cancelled";
    job.message = job.cancel_reason;
  } else if (WIFSIGNALED(status)) {
    job.state = "crashed";
    const std::string sig = !job.crash_signal.empty() ? job.crash_signal : strsignal(WTERMSIG(status));
    const std::string who = crashed.function.empty() ? "the worker" : crashed.function;
    job.message = who + " crashed: " + sig + " while " + doing + (crashed.where.empty() ? "" : " (" + crashed.where + ")");
  } else if (WIFEXITED(status) && WEXITSTATUS(status) == 0 && done) {
    job.state = "done";
  } else {
    job.state = "failed";
    if (job.message.empty())
      job.message = "the worker stopped while " + doing + " (exit status " +
                    std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + ")";
  }
  job.stall_seconds = 0;
  job.cv.notify_all();
}

}  // namespace

double now_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Reads the worker's two streams until it ends, then records how it
// ended and lets the stops waiting for it go on.
void Workers::watch(std::shared_ptr<Job> job, int out_fd, int err_fd) {
  std::thread err_reader([this, job, err_fd] { read_worker_stderr(job, err_fd, exe_, source_dir_); });
  const bool done = read_worker_stdout(job, out_fd);
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
  record_end(*job, status, done, exe_, source_dir_);
  std::lock_guard<std::mutex> lock(mu_);
  alive_.erase(job);
  gone_cv_.notify_all();
}

std::shared_ptr<Job> Workers::enter(const std::shared_ptr<Job>& job) {
  std::lock_guard<std::mutex> lock(mu_);
  job->id = ++next_id_;
  // One job of each kind at a time: a new one stops the one before, whose
  // image is not kept any more (only the latest job of a kind has one).
  std::shared_ptr<Job> previous = latest_[job->kind];
  latest_[job->kind] = job;
  if (previous) {
    cancel(*previous, "replaced by a newer " + std::string(job->kind == "debug" ? "call" : "job"));
    std::lock_guard<std::mutex> jl(previous->mu);
    previous->frame.reset();
    previous->bvh.reset();
  }
  jobs_[job->id] = job;
  // Keep the last few jobs' states for the page (and every kind's
  // latest); forget the rest.
  for (auto it = jobs_.begin(); jobs_.size() > 8 && it != jobs_.end();) {
    bool latest = false;
    for (const auto& [k, j] : latest_) latest = latest || j == it->second;
    it = latest ? std::next(it) : jobs_.erase(it);
  }
  return previous;
}

std::shared_ptr<Job> Workers::start(const std::string& kind, const RenderOptions& opts,
                                    const std::vector<std::string>& flags) {
  auto job = std::make_shared<Job>();
  job->kind = kind;
  job->opts = opts;
  job->started = job->last_seen = now_seconds();
  // Starts one at a time: concurrent requests each replace the one before,
  // and the one before is gone before the next worker exists.
  std::lock_guard<std::mutex> starting(start_mu_);
  if (std::shared_ptr<Job> previous = enter(job)) stop_and_wait({previous}, "");
  std::vector<std::string> args = {exe_, "--worker", kind == "normals" ? "render" : kind};
  args.insert(args.end(), flags.begin(), flags.end());
  pid_t pid = -1;
  int out_fd = -1, err_fd = -1;
  if (const int rc = spawn_worker(std::move(args), &pid, &out_fd, &err_fd)) {
    std::lock_guard<std::mutex> lock(job->mu);
    job->state = "failed";
    job->message = "cannot start the worker " + exe_ + ": " + std::strerror(rc);
    return job;
  }
  {
    std::lock_guard<std::mutex> lock(mu_);
    alive_.insert(job);
  }
  {
    std::lock_guard<std::mutex> lock(job->mu);
    job->pid = pid;
    // Stopped while it was being started (the server stopping, say).
    if (job->cancel_requested) ::kill(-pid, SIGKILL);
  }
  std::thread([this, job, out_fd, err_fd] { watch(job, out_fd, err_fd); }).detach();
  return job;
}

std::shared_ptr<Job> Workers::find(uint64_t id) {
  std::lock_guard<std::mutex> lock(mu_);
  auto it = jobs_.find(id);
  return it == jobs_.end() ? nullptr : it->second;
}

void Workers::stop_and_wait(const std::vector<std::shared_ptr<Job>>& jobs, const std::string& reason) {
  for (const auto& job : jobs) cancel(*job, reason);
  std::unique_lock<std::mutex> lock(mu_);
  // SIGKILL ends a process at once unless it is stuck in the kernel (a
  // dead disk, say); the server does not hang on one: a minute at most.
  gone_cv_.wait_for(lock, std::chrono::seconds(60), [&] {
    for (const auto& job : jobs)
      if (alive_.count(job)) return false;
    return true;
  });
}

void Workers::stop_kind(const std::string& kind, const std::string& reason) {
  std::vector<std::shared_ptr<Job>> jobs;
  {
    std::lock_guard<std::mutex> lock(mu_);
    for (const auto& job : alive_)
      if (job->kind == kind) jobs.push_back(job);
  }
  stop_and_wait(jobs, reason);
}

void Workers::stop(const std::shared_ptr<Job>& job, const std::string& reason) { stop_and_wait({job}, reason); }

std::vector<std::shared_ptr<Job>> Workers::stop_unwatched(double seconds) {
  std::vector<std::shared_ptr<Job>> stale;
  {
    std::lock_guard<std::mutex> lock(mu_);
    for (const auto& job : alive_) {
      std::lock_guard<std::mutex> jl(job->mu);
      if (job->state == "running" && job->waiting_polls == 0 && now_seconds() - job->last_seen > seconds)
        stale.push_back(job);
    }
  }
  char why[96];
  std::snprintf(why, sizeof why, "stopped: no page asked about it for %g s", seconds);
  stop_and_wait(stale, why);
  return stale;
}

void Workers::stop_all() {
  std::vector<std::shared_ptr<Job>> jobs;
  {
    std::lock_guard<std::mutex> lock(mu_);
    jobs.assign(alive_.begin(), alive_.end());
  }
  stop_and_wait(jobs, "the viewer is stopping");
}

size_t Workers::alive() {
  std::lock_guard<std::mutex> lock(mu_);
  return alive_.size();
}

void cancel(Job& job, const std::string& reason) {
  std::lock_guard<std::mutex> lock(job.mu);
  if (job.state != "running" || job.cancel_requested) return;
  job.cancel_requested = true;
  job.cancel_reason = reason;
  if (job.pid > 0) ::kill(-job.pid, SIGKILL);
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
  if (job.state == "running" && job.stall_seconds > 0)
    s << ",\"stalled\":{\"seconds\":" << num(job.stall_seconds + (now_seconds() - job.stall_at))
      << ",\"function\":" << json_quote(job.stall_function) << ",\"where\":" << json_quote(job.stall_where) << "}";
  s << ",\"wall\":" << num(now_seconds() - job.started) << "}";
  return s.str();
}


}  // namespace pt::viewer
