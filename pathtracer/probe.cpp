#include "pathtracer/probe.h"

#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>

namespace pt::probe {

namespace {

// A function gets this long to answer all its checks.
constexpr int kSecondsPerFunction = 20;

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\', out += c;
    else if (static_cast<unsigned char>(c) < 0x20) out += ' ';
    else out += c;
  }
  return out + "\"";
}

std::string number(double v) {
  if (!std::isfinite(v)) return "null";  // JSON has no NaN: null, which matches only a null
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

std::string checks_json(const std::vector<Check>& checks) {
  std::string s = "[";
  for (size_t i = 0; i < checks.size(); ++i) {
    const Check& c = checks[i];
    s += (i ? ",\n      " : "\n      ");
    s += "{\"name\": " + quoted(c.name) + ", \"abs\": " + number(c.abs) + ", \"rel\": " + number(c.rel) +
         ", \"values\": [";
    for (size_t k = 0; k < c.values.size(); ++k) s += (k ? ", " : "") + number(c.values[k]);
    s += "]}";
  }
  return s + "]";
}

// Runs one function's checks in a child process; its JSON comes back
// through a pipe. "crashed" or "timed out" when the child did not finish.
std::string run_one(const FunctionProbe& p, std::string* status) {
  int fds[2];
  if (pipe(fds) != 0) {
    *status = "not run (no pipe)";
    return "[]";
  }
  std::fflush(stdout);
  std::fflush(stderr);
  const pid_t pid = fork();
  if (pid < 0) {
    close(fds[0]), close(fds[1]);
    *status = "not run (no fork)";
    return "[]";
  }
  if (pid == 0) {
    close(fds[0]);
    // A crash ends the child as a crash, whatever handler the parent had.
    for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) std::signal(sig, SIG_DFL);
    std::string text;
    try {
      text = checks_json(p.run());
    } catch (...) {
      _exit(3);
    }
    for (size_t done = 0; done < text.size();) {
      const ssize_t n = write(fds[1], text.data() + done, text.size() - done);
      if (n <= 0) _exit(4);
      done += size_t(n);
    }
    _exit(0);
  }
  close(fds[1]);
  std::string text;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(kSecondsPerFunction);
  bool timed_out = false;
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) {
      timed_out = true;
      break;
    }
    pollfd pfd{fds[0], POLLIN, 0};
    const int r = poll(&pfd, 1, int(left.count()));
    if (r < 0) continue;  // interrupted: the deadline still holds
    if (r == 0) continue;
    char buf[4096];
    const ssize_t n = read(fds[0], buf, sizeof buf);
    if (n <= 0) break;  // the child closed its end
    text.append(buf, size_t(n));
    if (text.size() > (16u << 20)) break;
  }
  close(fds[0]);
  if (timed_out) kill(pid, SIGKILL);
  int wstatus = 0;
  while (waitpid(pid, &wstatus, 0) < 0 && errno == EINTR) {
  }
  if (timed_out) *status = "timed out";
  else if (WIFSIGNALED(wstatus)) *status = std::string("crashed (") + strsignal(WTERMSIG(wstatus)) + ")";
  else if (!WIFEXITED(wstatus) || WEXITSTATUS(wstatus) != 0) *status = "failed (threw or exited early)";
  else *status = "ok";
  return *status == "ok" ? text : "[]";
}

}  // namespace

int run_probes(const std::string& path, int max_part) {
  std::vector<FunctionProbe> all = probes_parts_1_2_5();
  for (FunctionProbe& p : probes_lighting()) all.push_back(p);
  for (FunctionProbe& p : probes_parts_3_6_9()) all.push_back(p);
  return run_probes(path, max_part, all);
}

int run_probes(const std::string& path, int max_part, const std::vector<FunctionProbe>& all) {
  std::string json = "{\"probes\": [";
  bool first = true;
  for (const FunctionProbe& p : all) {
    if (p.part > max_part) continue;
    std::string status;
    const std::string checks = run_one(p, &status);
    json += std::string(first ? "\n  " : ",\n  ") + "{\"function\": " + quoted(p.function) +
            ", \"part\": " + std::to_string(p.part) + ", \"status\": " + quoted(status) + ", \"checks\": " + checks +
            "}";
    first = false;
  }
  json += "\n]}\n";
  // Written whole or not at all: a temporary file, then renamed.
  const std::string tmp = path + ".part";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << json;
    if (!out) {
      std::fprintf(stderr, "pathtracer: error: %s: cannot write the function checks\n", path.c_str());
      std::remove(tmp.c_str());
      return 1;
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::fprintf(stderr, "pathtracer: error: %s: cannot write the function checks\n", path.c_str());
    std::remove(tmp.c_str());
    return 1;
  }
  return 0;
}

}  // namespace pt::probe
