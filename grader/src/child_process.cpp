#include "child_process.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace grader {

namespace {

double now_seconds() {
  using namespace std::chrono;
  return duration<double>(steady_clock::now().time_since_epoch()).count();
}

void set_limit(int resource, uint64_t soft, uint64_t hard) {
  struct rlimit rl;
  rl.rlim_cur = rlim_t(soft);
  rl.rlim_max = rlim_t(hard);
  setrlimit(resource, &rl);
}

// Waits a short while for the child without busy-spinning: the grader
// checks its children's clocks every 5 ms.
void pause_briefly() {
  struct timespec ts = {0, 5 * 1000 * 1000};
  nanosleep(&ts, nullptr);
}

}  // namespace

ChildResult run_child(const std::vector<std::string>& argv, const std::string& workdir,
                      const std::string& stdout_path, const std::string& stderr_path, const Limits& limits) {
  ChildResult result;
  if (argv.empty()) {
    result.error = "no program";
    return result;
  }
  // Everything the child needs is prepared before fork: between fork and
  // exec only async-signal-safe calls are allowed.
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const int out_fd = open(stdout_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  const int err_fd = open(stderr_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  const int null_fd = open("/dev/null", O_RDONLY | O_CLOEXEC);
  int status_pipe[2] = {-1, -1};  // exec failure is reported through it
  if (out_fd < 0 || err_fd < 0 || null_fd < 0 || pipe2(status_pipe, O_CLOEXEC) != 0) {
    result.error = std::string("cannot set up the child's files: ") + std::strerror(errno);
    for (int fd : {out_fd, err_fd, null_fd, status_pipe[0], status_pipe[1]})
      if (fd >= 0) close(fd);
    return result;
  }
  const uint64_t cpu = uint64_t(std::ceil(limits.cpu_seconds));
  const double start = now_seconds();
  const pid_t pid = fork();
  if (pid == 0) {
    setpgid(0, 0);
    dup2(null_fd, 0);
    dup2(out_fd, 1);
    dup2(err_fd, 2);
    set_limit(RLIMIT_CPU, cpu, cpu + 2);
    set_limit(RLIMIT_AS, limits.memory_bytes, limits.memory_bytes);
    set_limit(RLIMIT_FSIZE, limits.file_bytes, limits.file_bytes);
    set_limit(RLIMIT_CORE, 0, 0);
    if (chdir(workdir.c_str()) == 0) execv(args[0], args.data());
    const int e = errno;
    if (write(status_pipe[1], &e, sizeof e) < 0) _exit(127);
    _exit(127);
  }
  close(out_fd);
  close(err_fd);
  close(null_fd);
  close(status_pipe[1]);
  if (pid < 0) {
    result.error = std::string("fork failed: ") + std::strerror(errno);
    close(status_pipe[0]);
    return result;
  }
  setpgid(pid, pid);  // also from this side, so the kill below cannot miss
  int exec_errno = 0;
  const ssize_t got = read(status_pipe[0], &exec_errno, sizeof exec_errno);
  close(status_pipe[0]);

  // The stderr watch reads what the child wrote since the last look, line
  // by line; only the first 64 KB are watched (a TODO line comes first).
  const int watch_fd = !limits.stop_on_stderr ? -1 : open(stderr_path.c_str(), O_RDONLY | O_CLOEXEC);
  std::string pending;
  size_t watched = 0;
  const auto stderr_says_stop = [&]() {
    if (watch_fd < 0 || watched > (64u << 10)) return false;
    char buf[4096];
    ssize_t n;
    while ((n = read(watch_fd, buf, sizeof buf)) > 0) {
      watched += size_t(n);
      pending.append(buf, size_t(n));
      size_t eol;
      while ((eol = pending.find('\n')) != std::string::npos) {
        const std::string line = pending.substr(0, eol);
        pending.erase(0, eol + 1);
        if (limits.stop_on_stderr(line)) {
          result.stop_line = line;
          return true;
        }
      }
      if (watched > (64u << 10)) break;
    }
    return false;
  };

  int status = 0;
  for (;;) {
    const pid_t done = waitpid(pid, &status, WNOHANG);
    if (done == pid) break;
    if (done < 0 && errno != EINTR) break;
    if (stderr_says_stop()) {
      result.stopped = true;
      kill(-pid, SIGKILL);
      kill(pid, SIGKILL);
      while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
      }
      break;
    }
    if (now_seconds() - start > limits.wall_seconds) {
      result.timed_out = true;
      kill(-pid, SIGKILL);
      kill(pid, SIGKILL);
      while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
      }
      break;
    }
    pause_briefly();
  }
  result.seconds = now_seconds() - start;
  if (watch_fd >= 0) close(watch_fd);
  kill(-pid, SIGKILL);  // whatever it forked and left behind
  if (got == sizeof exec_errno) {
    result.error = std::string("cannot run ") + argv[0] + ": " + std::strerror(exec_errno);
    return result;
  }
  result.started = true;
  if (!result.timed_out && !result.stopped) {
    if (WIFEXITED(status)) result.exit_code = WEXITSTATUS(status);
    if (WIFSIGNALED(status)) result.signal = WTERMSIG(status);
  }
  return result;
}

std::string describe(const ChildResult& r, const Limits& limits) {
  char buf[160];
  if (!r.started) return "could not start: " + r.error;
  if (r.stopped) return "stopped after it printed \"" + r.stop_line + "\"";
  if (r.timed_out) {
    std::snprintf(buf, sizeof buf, "timed out after %.0f s (killed)", limits.wall_seconds);
    return buf;
  }
  if (r.signal == SIGXCPU) {
    std::snprintf(buf, sizeof buf, "used more than its %.0f s of CPU time (killed by SIGXCPU)", limits.cpu_seconds);
    return buf;
  }
  if (r.signal == SIGXFSZ) {
    std::snprintf(buf, sizeof buf, "wrote a file larger than the %.0f MB limit (killed by SIGXFSZ)",
                  double(limits.file_bytes) / (1 << 20));
    return buf;
  }
  if (r.signal != 0) {
    std::snprintf(buf, sizeof buf, "crashed: killed by signal %d (%s)", r.signal, strsignal(r.signal));
    return buf;
  }
  std::snprintf(buf, sizeof buf, "exited with status %d", r.exit_code);
  return buf;
}

std::string read_text_sanitized(const std::string& path, size_t max_bytes) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return "";
  std::string text(max_bytes, '\0');
  in.read(&text[0], std::streamsize(max_bytes));
  text.resize(size_t(in.gcount()));
  for (char& c : text) {
    const unsigned char u = static_cast<unsigned char>(c);
    if (!(u == '\n' || u == '\t' || (u >= 0x20 && u < 0x7F))) c = '?';
  }
  return text;
}

uint64_t directory_bytes(const std::string& dir) {
  uint64_t total = 0;
  std::error_code ec;
  for (auto it = std::filesystem::recursive_directory_iterator(dir, ec);
       !ec && it != std::filesystem::recursive_directory_iterator(); it.increment(ec)) {
    std::error_code size_ec;
    if (it->is_regular_file(size_ec)) {
      const auto n = it->file_size(size_ec);
      if (!size_ec) total += n;
    }
  }
  return total;
}

}  // namespace grader
