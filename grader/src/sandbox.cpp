#include "grader/src/sandbox.h"

#include <dirent.h>
#include <fcntl.h>
#include <grp.h>
#include <pwd.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <map>
#include <sstream>
#include <stdexcept>

#include "grader/src/child_process.h"

namespace grader {

namespace fs = std::filesystem;

const char* sandbox_mode_name(SandboxMode mode) {
  switch (mode) {
    case SandboxMode::None: return "none";
    case SandboxMode::Bwrap: return "bwrap";
    case SandboxMode::User: return "user";
  }
  return "?";
}

bool parse_sandbox_mode(const std::string& s, SandboxMode* mode) {
  for (SandboxMode m : {SandboxMode::None, SandboxMode::Bwrap, SandboxMode::User})
    if (s == sandbox_mode_name(m)) {
      *mode = m;
      return true;
    }
  return false;
}

namespace {

thread_local int tls_job_slot = 0;

// bwrap's path: the first on PATH, else Debian's.
std::string bwrap_path() {
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path ? path : "/usr/bin:/bin");
  for (std::string d; std::getline(dirs, d, ':');) {
    const std::string p = (d.empty() ? "." : d) + "/bwrap";
    if (access(p.c_str(), X_OK) == 0) return p;
  }
  return "/usr/bin/bwrap";
}

// The part of the machine a sandboxed render sees besides its own folders:
// /usr read-only, the top-level links into it (merged /usr) or the folders
// themselves, the dynamic loader's cache, a new /proc and /dev, and a
// fresh /tmp of at most 256 MB.
std::vector<std::string> bwrap_base() {
  std::vector<std::string> a = {bwrap_path(), "--unshare-all", "--die-with-parent", "--new-session",
                                "--cap-drop", "ALL", "--ro-bind", "/usr", "/usr"};
  for (const char* top : {"bin", "sbin", "lib", "lib32", "lib64", "libx32"}) {
    const std::string p = std::string("/") + top;
    std::error_code ec;
    const fs::file_status st = fs::symlink_status(p, ec);
    if (ec || !fs::exists(st)) continue;
    if (fs::is_symlink(st)) {
      const fs::path target = fs::read_symlink(p, ec);
      if (!ec) a.insert(a.end(), {"--symlink", target.string(), p});
    } else if (fs::is_directory(st)) {
      a.insert(a.end(), {"--ro-bind", p, p});
    }
  }
  a.insert(a.end(), {"--ro-bind-try", "/etc/ld.so.cache", "/etc/ld.so.cache", "--proc", "/proc", "--dev", "/dev",
                     "--size", std::to_string(256u << 20), "--tmpfs", "/tmp"});
  return a;
}

const char* const kInside = "/sandbox";

// Runs `task` in a child process as `account` (when there is one) and
// returns its exit status (-1 when it could not run).
template <class F>
int as_account(const Account* account, F task) {
  pid_t pid;
  {
    std::lock_guard<std::mutex> lock(fork_mutex());
    pid = fork();
  }
  if (pid < 0) return -1;
  if (pid == 0) {
    if (account && (setgroups(0, nullptr) != 0 || setgid(account->gid) != 0 || setuid(account->uid) != 0)) _exit(120);
    _exit(task());
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Every path under `root` (itself first), at most `limit` of them.
std::vector<std::string> paths_under(const std::string& root, size_t limit) {
  std::vector<std::string> out = {root};
  std::error_code ec;
  if (!fs::is_directory(fs::symlink_status(root, ec))) return out;
  for (auto it = fs::recursive_directory_iterator(root, fs::directory_options::skip_permission_denied, ec);
       !ec && it != fs::recursive_directory_iterator() && out.size() < limit; it.increment(ec))
    out.push_back(it->path().string());
  return out;
}

bool copy_file_to(const std::string& from, const std::string& to, mode_t mode, std::string* error) {
  // No fork while the copy is open for writing (fork_mutex).
  std::lock_guard<std::mutex> lock(fork_mutex());
  std::error_code ec;
  fs::copy_file(from, to, fs::copy_options::overwrite_existing, ec);
  if (!ec && chmod(to.c_str(), mode) != 0) ec = std::error_code(errno, std::generic_category());
  if (ec) *error = "cannot copy " + from + " into the sandbox: " + ec.message();
  return !ec;
}

}  // namespace

const Account* Sandbox::account() const {
  if (accounts.empty()) return nullptr;
  return &accounts[size_t(tls_job_slot) % accounts.size()];
}

void set_job_slot(int slot) { tls_job_slot = slot; }
int job_slot() { return tls_job_slot; }

std::vector<Account> lookup_accounts(const std::vector<std::string>& names) {
  std::vector<Account> out;
  for (const std::string& list : names) {
    std::istringstream in(list);
    for (std::string name; std::getline(in, name, ',');) {
      if (name.empty()) continue;
      struct passwd pw, *found = nullptr;
      char buf[4096];
      if (getpwnam_r(name.c_str(), &pw, buf, sizeof buf, &found) != 0 || !found)
        throw std::runtime_error("--sandbox-user " + name + ": no such account");
      if (pw.pw_uid == 0) throw std::runtime_error("--sandbox-user " + name + ": is root; give an unprivileged account");
      out.push_back({name, pw.pw_uid, pw.pw_gid});
    }
  }
  return out;
}

void check_sandbox(const Sandbox& sandbox, int jobs, const std::vector<std::string>& secrets) {
  if (!sandbox.on()) return;
  const std::string mode = sandbox_mode_name(sandbox.mode);
  if (geteuid() == 0 && sandbox.accounts.empty())
    throw std::runtime_error("--sandbox " + mode +
                             " as root needs --sandbox-user ACCOUNT[,ACCOUNT...]: submitted code never runs as root");
  if (geteuid() != 0 && !sandbox.accounts.empty())
    throw std::runtime_error("--sandbox-user: only root can render as another account");
  if (!sandbox.accounts.empty() && int(sandbox.accounts.size()) < jobs)
    throw std::runtime_error("--sandbox-user gives " + std::to_string(sandbox.accounts.size()) + " account(s) for " +
                             std::to_string(jobs) + " jobs: one account per job at a time");
  std::error_code ec;
  if (!fs::is_directory(sandbox.root, ec)) throw std::runtime_error("--sandbox-tmp " + sandbox.root + ": not a folder");
  if (sandbox.mode == SandboxMode::Bwrap) {
    // bwrap must start here, as the account that renders.
    std::vector<std::string> argv = bwrap_base();
    argv.insert(argv.end(), {"--remount-ro", "/", "--", "/usr/bin/true"});
    const std::string log = (fs::path(sandbox.root) / ("pt-bwrap-probe-" + std::to_string(getpid()) + ".txt")).string();
    Limits limits;
    limits.wall_seconds = 60;
    if (!sandbox.accounts.empty()) limits.run_uid = sandbox.accounts[0].uid, limits.run_gid = sandbox.accounts[0].gid;
    limits.clear_environment = true;
    const ChildResult r = run_child(argv, "/", "/dev/null", log, limits);
    const std::string err = read_text_sanitized(log, 400);
    fs::remove(log, ec);
    if (!r.started || r.exit_code != 0)
      throw std::runtime_error("--sandbox bwrap: bubblewrap cannot run here (" + describe(r, limits) +
                               (err.empty() ? "" : ": " + err.substr(0, err.find('\n'))) +
                               "); install Debian's bubblewrap, allow user namespaces, or use --sandbox user");
    return;
  }
  // Mode User: the accounts' own permissions are the only wall.
  std::vector<std::string> paths;
  for (const std::string& s : secrets)
    for (const std::string& p : paths_under(s, 4000)) paths.push_back(p);
  for (const Account& a : sandbox.accounts) {
    std::string readable;
    int pipe_fd[2];
    if (pipe(pipe_fd) != 0) throw std::runtime_error("cannot check the sandbox: pipe failed");
    as_account(&a, [&] {
      close(pipe_fd[0]);
      for (const std::string& p : paths) {
        const int fd = open(p.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
        if (fd >= 0) {
          close(fd);
          const std::string line = p + "\n";
          if (write(pipe_fd[1], line.data(), line.size()) < 0) return 3;
          return 1;
        }
      }
      return 0;
    });
    close(pipe_fd[1]);
    char buf[1024];
    ssize_t n;
    while ((n = read(pipe_fd[0], buf, sizeof buf)) > 0) readable.append(buf, size_t(n));
    close(pipe_fd[0]);
    if (!readable.empty())
      throw std::runtime_error("--sandbox user: account " + a.name + " can read " +
                               readable.substr(0, readable.find('\n')) +
                               "; make the references, case lists, grader and output folder readable by root only");
  }
}

void lock_accounts(const Sandbox& sandbox, const std::string& lock_dir) {
  for (const Account& a : sandbox.accounts) {
    const std::string path = lock_dir + "/pt-grader-account-" + a.name + ".lock";
    // Kept open (and locked) until the process ends.
    const int fd = open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0600);
    if (fd < 0) throw std::runtime_error("cannot open " + path + " to lock the account " + a.name + ": " + std::strerror(errno));
    if (flock(fd, LOCK_EX | LOCK_NB) == 0) continue;
    std::fprintf(stderr, "grader: waiting for another grader that renders as %s (%s)\n", a.name.c_str(), path.c_str());
    while (flock(fd, LOCK_EX) != 0)
      if (errno != EINTR) throw std::runtime_error("cannot lock " + path + ": " + std::strerror(errno));
  }
}

namespace {

// A file's bytes, or nothing when it cannot be read whole.
bool read_whole(const std::string& path, std::string* out) {
  const int fd = open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return false;
  out->clear();
  char buf[1 << 16];
  ssize_t n;
  while ((n = read(fd, buf, sizeof buf)) > 0) out->append(buf, size_t(n));
  close(fd);
  return n == 0;
}

}  // namespace

void check_no_copies(const Sandbox& sandbox, const std::vector<std::string>& keys, const std::string& search_root) {
  if (sandbox.mode != SandboxMode::User || sandbox.accounts.empty()) return;
  // The key's files by size, then by bytes: only a file of a key file's
  // size is read. Small files (a few bytes could match anything) are left
  // out; every reference image and case list is far larger.
  std::map<uintmax_t, std::vector<size_t>> by_size;  // size -> hashes of the bytes
  for (const std::string& k : keys)
    for (const std::string& p : paths_under(k, 100000)) {
      std::error_code ec;
      if (!fs::is_regular_file(fs::symlink_status(p, ec))) continue;
      const uintmax_t size = fs::file_size(p, ec);
      std::string bytes;
      if (!ec && size >= 256 && read_whole(p, &bytes)) by_size[size].push_back(std::hash<std::string>()(bytes));
    }
  if (by_size.empty()) return;
  for (const Account& a : sandbox.accounts) {
    int pipe_fd[2];
    if (pipe(pipe_fd) != 0) throw std::runtime_error("cannot check the sandbox: pipe failed");
    as_account(&a, [&] {
      close(pipe_fd[0]);
      // As the account: every folder it may enter, no link followed, not
      // the kernel's file systems. A folder that cannot be read, or an
      // entry gone meanwhile (other runs' files in /tmp), is passed over;
      // the walk goes on.
      std::vector<std::string> folders = {search_root};
      std::string bytes;
      while (!folders.empty()) {
        const std::string dir = folders.back();
        folders.pop_back();
        DIR* d = opendir(dir.c_str());
        if (!d) continue;
        while (const dirent* e = readdir(d)) {
          const std::string name = e->d_name;
          if (name == "." || name == "..") continue;
          const std::string p = (dir == "/" ? "" : dir) + "/" + name;
          if (p == "/proc" || p == "/sys" || p == "/dev" || p == "/run") continue;
          struct stat st;
          if (lstat(p.c_str(), &st) != 0) continue;
          if (S_ISDIR(st.st_mode)) {
            folders.push_back(p);
            continue;
          }
          if (!S_ISREG(st.st_mode)) continue;
          const auto same = by_size.find(uintmax_t(st.st_size));
          if (same == by_size.end() || !read_whole(p, &bytes)) continue;
          const size_t h = std::hash<std::string>()(bytes);
          for (size_t key : same->second)
            if (h == key) {
              closedir(d);
              const std::string line = p + "\n";
              if (write(pipe_fd[1], line.data(), line.size()) < 0) return 3;
              return 1;
            }
        }
        closedir(d);
      }
      return 0;
    });
    close(pipe_fd[1]);
    std::string found;
    char buf[1024];
    ssize_t n;
    while ((n = read(pipe_fd[0], buf, sizeof buf)) > 0) found.append(buf, size_t(n));
    close(pipe_fd[0]);
    if (!found.empty())
      throw std::runtime_error("--sandbox user: account " + a.name + " can read " + found.substr(0, found.find('\n')) +
                               ", a copy of a hidden case's file; in user mode the accounts see every file the "
                               "machine lets others read: remove the copy or make it unreadable, or use --sandbox bwrap");
  }
}

Staging::~Staging() {
  if (dir_.empty()) return;
  std::error_code ec;
  fs::remove_all(dir_, ec);
}

bool Staging::stage(const Sandbox& sandbox, const Account* account, const std::vector<std::string>& inputs,
                    std::string* error) {
  mode_ = sandbox.mode;
  std::string templ = (fs::path(sandbox.root) / "pt-render-XXXXXX").string();
  if (!mkdtemp(templ.data())) {
    *error = "cannot make a staging folder in " + sandbox.root + ": " + std::strerror(errno);
    return false;
  }
  dir_ = templ;
  const std::string in = dir_ + "/in", out = dir_ + "/out";
  if (chmod(dir_.c_str(), 0711) != 0 || mkdir(in.c_str(), 0755) != 0 || mkdir(out.c_str(), 0700) != 0 ||
      chmod(in.c_str(), 0755) != 0) {
    *error = "cannot set up " + dir_ + ": " + std::strerror(errno);
    return false;
  }
  if (account && chown(out.c_str(), account->uid, account->gid) != 0) {
    *error = "cannot give " + out + " to " + account->name + ": " + std::strerror(errno);
    return false;
  }
  for (const std::string& input : inputs) {
    const std::string to = in + "/" + fs::path(input).filename().string();
    std::error_code ec;
    if (fs::exists(fs::symlink_status(to, ec))) continue;  // the same file named twice
    const bool executable = access(input.c_str(), X_OK) == 0 && fs::is_regular_file(input, ec);
    if (!copy_file_to(input, to, executable ? 0755 : 0644, error)) return false;
  }
  return true;
}

std::string Staging::input_path(const std::string& input) const {
  const std::string name = fs::path(input).filename().string();
  return (mode_ == SandboxMode::Bwrap ? std::string(kInside) : dir_) + "/in/" + name;
}

std::string Staging::out_path() const { return (mode_ == SandboxMode::Bwrap ? std::string(kInside) : dir_) + "/out"; }

std::vector<std::string> Staging::command(const std::vector<std::string>& argv) const {
  if (mode_ != SandboxMode::Bwrap) return argv;
  std::vector<std::string> a = bwrap_base();
  a.insert(a.end(), {"--ro-bind", dir_ + "/in", std::string(kInside) + "/in", "--bind", dir_ + "/out",
                     std::string(kInside) + "/out", "--remount-ro", "/", "--chdir", std::string(kInside) + "/out",
                     "--clearenv", "--setenv", "PATH", "/usr/bin:/bin", "--setenv", "HOME",
                     std::string(kInside) + "/out", "--"});
  a.insert(a.end(), argv.begin(), argv.end());
  return a;
}

void Staging::collect(const std::vector<std::string>& names, const std::string& dest, uint64_t max_bytes,
                      std::vector<std::string>* refused) const {
  for (const std::string& name : names) {
    const std::string from = dir_ + "/out/" + name, to = dest + "/" + name;
    struct stat st;
    if (lstat(from.c_str(), &st) != 0) continue;  // not written
    // O_NOFOLLOW and the checks on the open file: what is read is what was
    // checked, even if the render's account swaps the name meanwhile.
    const int fd = open(from.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0 || fstat(fd, &st) != 0 || !S_ISREG(st.st_mode) || st.st_nlink != 1 || uint64_t(st.st_size) > max_bytes) {
      if (fd >= 0) close(fd);
      refused->push_back(name);
      continue;
    }
    const int out = open(to.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC, 0644);
    bool ok = out >= 0;
    char buf[1 << 16];
    ssize_t n;
    while (ok && (n = read(fd, buf, sizeof buf)) > 0) ok = write(out, buf, size_t(n)) == n;
    close(fd);
    if (out >= 0) close(out);
    if (!ok) refused->push_back(name);
  }
}

void kill_account_processes(const Account& account) {
  as_account(&account, [] {
    // kill(-1) reaches every process of the account but this one; repeat
    // until none is left (a process may fork while it is being killed).
    for (int round = 0; round < 100; ++round)
      if (kill(-1, SIGKILL) != 0 && errno == ESRCH) return 0;
    return 1;
  });
}

}  // namespace grader
