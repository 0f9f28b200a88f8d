#include "grader/src/child_process.h"

#include <fcntl.h>
#include <grp.h>
#include <linux/audit.h>
#include <linux/filter.h>
#include <linux/seccomp.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/syscall.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <cerrno>
#include <cstddef>
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

// The files the child writes to and reads from, and the pipe through which
// it reports a failed exec; all opened close-on-exec.
struct ChildFiles {
  int out = -1, err = -1, null = -1;
  int status_pipe[2] = {-1, -1};
  bool ok() const { return out >= 0 && err >= 0 && null >= 0 && status_pipe[0] >= 0; }
  void close_all() const {
    for (int fd : {out, err, null, status_pipe[0], status_pipe[1]})
      if (fd >= 0) close(fd);
  }
};

ChildFiles open_child_files(const std::string& stdout_path, const std::string& stderr_path) {
  ChildFiles f;
  f.out = open(stdout_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  f.err = open(stderr_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  f.null = open("/dev/null", O_RDONLY | O_CLOEXEC);
  if (f.out >= 0 && f.err >= 0 && f.null >= 0 && pipe2(f.status_pipe, O_CLOEXEC) != 0) {
    f.status_pipe[0] = f.status_pipe[1] = -1;
  }
  return f;
}

// Installs a seccomp filter that refuses IPv4 and IPv6 sockets (EACCES) and
// kills a process that makes system calls of another architecture (the
// 32-bit socketcall would go around the check). False when the kernel
// refuses the filter.
#if defined(__x86_64__)
constexpr unsigned kAuditArch = AUDIT_ARCH_X86_64;
#elif defined(__aarch64__)
constexpr unsigned kAuditArch = AUDIT_ARCH_AARCH64;
#else
constexpr unsigned kAuditArch = 0;  // not supported: forbid_network() fails
#endif

bool forbid_network() {
  if (kAuditArch == 0) {
    errno = ENOSYS;
    return false;
  }
  static struct sock_filter code[] = {
      BPF_STMT(BPF_LD | BPF_W | BPF_ABS, offsetof(struct seccomp_data, arch)),
      BPF_JUMP(BPF_JMP | BPF_JEQ | BPF_K, kAuditArch, 1, 0),
      BPF_STMT(BPF_RET | BPF_K, SECCOMP_RET_KILL_PROCESS),
      BPF_STMT(BPF_LD | BPF_W | BPF_ABS, offsetof(struct seccomp_data, nr)),
      BPF_JUMP(BPF_JMP | BPF_JEQ | BPF_K, __NR_socket, 0, 4),
      BPF_STMT(BPF_LD | BPF_W | BPF_ABS, offsetof(struct seccomp_data, args[0])),
      BPF_JUMP(BPF_JMP | BPF_JEQ | BPF_K, AF_INET, 1, 0),
      BPF_JUMP(BPF_JMP | BPF_JEQ | BPF_K, AF_INET6, 0, 1),
      BPF_STMT(BPF_RET | BPF_K, SECCOMP_RET_ERRNO | (EACCES & SECCOMP_RET_DATA)),
      BPF_STMT(BPF_RET | BPF_K, SECCOMP_RET_ALLOW),
  };
  static struct sock_fprog program = {sizeof code / sizeof code[0], code};
  return prctl(PR_SET_SECCOMP, SECCOMP_MODE_FILTER, &program, 0, 0) == 0;
}

// The child's side of fork: only async-signal-safe calls from here to exec.
[[noreturn]] void become_child(const ChildFiles& f, char* const* args, const std::string& workdir,
                               uint64_t cpu, const Limits& limits) {
  setpgid(0, 0);
  dup2(f.null, 0);
  dup2(f.out, 1);
  dup2(f.err, 2);
  set_limit(RLIMIT_CPU, cpu, cpu + 2);
  set_limit(RLIMIT_AS, limits.memory_bytes, limits.memory_bytes);
  set_limit(RLIMIT_FSIZE, limits.file_bytes, limits.file_bytes);
  set_limit(RLIMIT_CORE, 0, 0);
  if (limits.run_uid >= 0 || limits.clear_environment) prctl(PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0);
  if (limits.run_uid >= 0) {
    if (setgroups(0, nullptr) != 0 || setgid(gid_t(limits.run_gid)) != 0 || setuid(uid_t(limits.run_uid)) != 0 ||
        getuid() != uid_t(limits.run_uid)) {
      const int e = errno ? errno : EPERM;
      if (write(f.status_pipe[1], &e, sizeof e) < 0) _exit(127);
      _exit(127);
    }
    set_limit(RLIMIT_NPROC, kMaxProcesses, kMaxProcesses);
  }
  if (limits.no_network && !forbid_network()) {
    const int e = errno ? errno : EPERM;
    if (write(f.status_pipe[1], &e, sizeof e) < 0) _exit(127);
    _exit(127);
  }
  static char path_variable[] = "PATH=/usr/bin:/bin";
  static char* const clean_environment[] = {path_variable, nullptr};
  if (chdir(workdir.c_str()) == 0) {
    if (limits.clear_environment) execve(args[0], args, clean_environment);
    else execv(args[0], args);
  }
  const int e = errno;
  if (write(f.status_pipe[1], &e, sizeof e) < 0) _exit(127);
  _exit(127);
}

// Reads what the child wrote to stderr since the last look, line by line;
// only the first 64 KB are watched (a TODO line comes first).
class StderrWatch {
 public:
  StderrWatch(const std::string& stderr_path, const Limits& limits)
      : limits_(limits), fd_(!limits.stop_on_stderr ? -1 : open(stderr_path.c_str(), O_RDONLY | O_CLOEXEC)) {}
  ~StderrWatch() {
    if (fd_ >= 0) close(fd_);
  }
  StderrWatch(const StderrWatch&) = delete;
  StderrWatch& operator=(const StderrWatch&) = delete;

  // True when a new line asks to stop the child; the line goes to stop_line.
  bool says_stop(std::string& stop_line) {
    if (fd_ < 0 || watched_ > (64u << 10)) return false;
    char buf[4096];
    ssize_t n;
    while ((n = read(fd_, buf, sizeof buf)) > 0) {
      watched_ += size_t(n);
      pending_.append(buf, size_t(n));
      size_t eol;
      while ((eol = pending_.find('\n')) != std::string::npos) {
        const std::string line = pending_.substr(0, eol);
        pending_.erase(0, eol + 1);
        if (limits_.stop_on_stderr(line)) {
          stop_line = line;
          return true;
        }
      }
      if (watched_ > (64u << 10)) break;
    }
    return false;
  }

 private:
  const Limits& limits_;
  const int fd_;
  std::string pending_;
  size_t watched_ = 0;
};

void kill_and_reap(pid_t pid, int& status) {
  kill(-pid, SIGKILL);
  kill(pid, SIGKILL);
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
}

// Polls the child until it ends, its stderr dooms it or its wall-clock time
// runs out; returns its wait status and sets stopped / timed_out.
int wait_for_child(pid_t pid, double start, const Limits& limits, StderrWatch& watch, ChildResult& result) {
  int status = 0;
  for (;;) {
    const pid_t done = waitpid(pid, &status, WNOHANG);
    if (done == pid) break;
    if (done < 0 && errno != EINTR) break;
    if (watch.says_stop(result.stop_line)) {
      result.stopped = true;
      kill_and_reap(pid, status);
      break;
    }
    if (now_seconds() - start > limits.wall_seconds) {
      result.timed_out = true;
      kill_and_reap(pid, status);
      break;
    }
    pause_briefly();
  }
  return status;
}

}  // namespace

std::mutex& fork_mutex() {
  static std::mutex m;
  return m;
}

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
  const ChildFiles files = open_child_files(stdout_path, stderr_path);
  if (!files.ok()) {
    result.error = std::string("cannot set up the child's files: ") + std::strerror(errno);
    files.close_all();
    return result;
  }
  const uint64_t cpu = uint64_t(std::ceil(limits.cpu_seconds));
  const double start = now_seconds();
  pid_t pid;
  {
    std::lock_guard<std::mutex> lock(fork_mutex());
    pid = fork();
    if (pid == 0) become_child(files, args.data(), workdir, cpu, limits);
  }
  for (int fd : {files.out, files.err, files.null, files.status_pipe[1]}) close(fd);
  if (pid < 0) {
    result.error = std::string("fork failed: ") + std::strerror(errno);
    close(files.status_pipe[0]);
    return result;
  }
  setpgid(pid, pid);  // also from this side, so the kill below cannot miss
  int exec_errno = 0;
  const ssize_t got = read(files.status_pipe[0], &exec_errno, sizeof exec_errno);
  close(files.status_pipe[0]);

  int status = 0;
  {
    StderrWatch watch(stderr_path, limits);
    status = wait_for_child(pid, start, limits, watch, result);
    result.seconds = now_seconds() - start;
  }
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
