// Runs an untrusted program (a student's pathtracer) in a child process with
// a wall-clock timeout and resource limits, and reports how it ended.
#pragma once
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <vector>


namespace grader {

struct Limits {
  double wall_seconds = 60;      // killed (with its whole process group) after this
  double cpu_seconds = 240;      // RLIMIT_CPU: SIGXCPU after this much CPU time
  uint64_t memory_bytes = 4ull << 30;   // RLIMIT_AS
  uint64_t file_bytes = 256ull << 20;   // RLIMIT_FSIZE: the largest file it may write
  // When set: the child is stopped (killed with its group) as soon as this
  // returns true for a line of its stderr; ChildResult::stop_line says
  // which. For a render that says it cannot do what the case needs
  // ("TODO: implement Part 3: ..."), so that an unfinished build is not
  // left to run into the timeout.
  std::function<bool(const std::string& line)> stop_on_stderr;
  // When >= 0 (the grader runs as root): the child drops to this user and
  // group (no supplementary groups) before it runs anything, may not gain
  // privileges again (no set-user-ID programs), and may have at most
  // kMaxProcesses processes of that user at a time.
  int run_uid = -1, run_gid = -1;
  // The child gets an environment of PATH alone instead of the grader's.
  bool clear_environment = false;
  // The child (and all it starts) may not open an IPv4 or IPv6 socket: a
  // seccomp filter answers socket(AF_INET/AF_INET6, ...) with EACCES. For
  // a sandbox without a network namespace (sandbox.h, mode User).
  bool no_network = false;
};

constexpr int kMaxProcesses = 512;

struct ChildResult {
  bool started = false;     // false: fork or exec failed (see `error`)
  bool timed_out = false;   // killed at the wall-clock limit
  int exit_code = -1;       // when it exited normally
  int signal = 0;           // when a signal ended it
  double seconds = 0;       // wall-clock time
  std::string error;        // why it could not start
  bool stopped = false;     // stopped for Limits::stop_on_stderr
  std::string stop_line;    // the line that stopped it
};

// Runs argv[0] (a path) with its arguments in `workdir`, stdout and stderr
// written to the files `stdout_path` and `stderr_path`, stdin from
// /dev/null. The child leads a new process group; when the child ends (or
// times out) every process left in that group is killed, so forked
// children that hang cannot outlive the case. Safe to call from several
// threads at once.
ChildResult run_child(const std::vector<std::string>& argv, const std::string& workdir,
                      const std::string& stdout_path, const std::string& stderr_path, const Limits& limits);

// Held while the grader forks a child, and while it writes a file that a
// child will run (a sandbox's copy of the binary): a child forked while a
// thread has such a file open for writing would keep it open until its
// exec, and running the file then fails with "Text file busy".
std::mutex& fork_mutex();

// "exited with status 3", "killed by signal 11 (Segmentation fault)",
// "timed out after 60 s", "could not start: ...", "stopped after it printed ..."
std::string describe(const ChildResult& r, const Limits& limits);

// The first `max_bytes` of a file with every byte that is not printable
// ASCII, a tab or a newline replaced by '?' (student output goes into JSON
// and HTML reports).
std::string read_text_sanitized(const std::string& path, size_t max_bytes);

// The total size of the regular files under `dir` (recursively).
uint64_t directory_bytes(const std::string& dir);

}  // namespace grader
