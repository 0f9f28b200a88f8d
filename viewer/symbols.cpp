#include "viewer/symbols.h"

#include <cxxabi.h>
#include <dlfcn.h>
#include <fcntl.h>
#include <link.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>

extern char** environ;

namespace pt::viewer {

namespace {

struct Frame {
  std::string function;  // demangled
  std::string file_line;  // "/path/file.cpp:23", or "??:?"
};

// Each address's frames, innermost first (addr2line -i: the functions
// inlined there, then the one they were inlined into). Empty when
// addr2line cannot be run.
std::vector<std::vector<Frame>> addr2line(const std::string& exe, const std::vector<uint64_t>& addresses) {
  std::vector<std::vector<Frame>> out;
  if (addresses.empty()) return out;
  std::vector<std::string> args = {"addr2line", "-a", "-f", "-C", "-i", "-e", exe};
  char buf[32];
  for (uint64_t a : addresses) {
    std::snprintf(buf, sizeof buf, "0x%llx", (unsigned long long)a);
    args.push_back(buf);
  }
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  int pipe_fds[2];
  if (::pipe2(pipe_fds, O_CLOEXEC) != 0) return out;
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(&fa, pipe_fds[1], 1);
  posix_spawn_file_actions_addopen(&fa, 2, "/dev/null", O_WRONLY, 0);
  pid_t pid;
  const int rc = posix_spawnp(&pid, "addr2line", &fa, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  ::close(pipe_fds[1]);
  std::string text;
  if (rc == 0) {
    char chunk[4096];
    ssize_t n;
    while ((n = ::read(pipe_fds[0], chunk, sizeof chunk)) > 0 || (n < 0 && errno == EINTR))
      if (n > 0) text.append(chunk, size_t(n));
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) text.clear();
  }
  ::close(pipe_fds[0]);
  // "0x<address>" starts each address's lines; then pairs of lines.
  std::istringstream lines(text);
  std::string line, function;
  bool have_function = false;
  while (std::getline(lines, line)) {
    if (line.rfind("0x", 0) == 0) {
      out.emplace_back();
      have_function = false;
    } else if (!out.empty() && !have_function) {
      function = line;
      have_function = true;
    } else if (!out.empty()) {
      out.back().push_back({function, line});
      have_function = false;
    }
  }
  if (out.size() != addresses.size()) out.clear();
  return out;
}

// Without addr2line: the program's exported symbols, read from this
// process, which runs the same file as the worker.
uintptr_t g_bias = 0;
int own_bias(dl_phdr_info* info, size_t, void*) {
  g_bias = info->dlpi_addr;
  return 1;
}
std::vector<Frame> exported_symbol(uint64_t offset) {
  if (!g_bias) dl_iterate_phdr(own_bias, nullptr);
  Dl_info info = {};
  if (!dladdr(reinterpret_cast<void*>(g_bias + offset), &info) || !info.dli_sname) return {};
  int status = 0;
  char* d = abi::__cxa_demangle(info.dli_sname, nullptr, nullptr, &status);
  std::string name = status == 0 && d ? d : info.dli_sname;
  std::free(d);
  return {{name, "??:?"}};
}

// "/src/stages/part1_raytracing/triangle.cpp:23 (discriminator 2)" ->
// "stages/part1_raytracing/triangle.cpp:23"; "" without debug information.
std::string file_line(std::string s, const std::string& source_dir) {
  if (s.empty() || s[0] == '?') return "";
  if (const size_t d = s.find(" (discriminator"); d != std::string::npos) s.erase(d);
  if (s.size() >= 2 && s.compare(s.size() - 2, 2, ":?") == 0) return "";
  if (s.size() >= 2 && s.compare(s.size() - 2, 2, ":0") == 0) return "";
  // "/src/build/x/../../viewer/a.cpp:3" (a compiler given relative paths,
  // as under ccache) -> "/src/viewer/a.cpp:3".
  if (const size_t colon = s.rfind(':'); colon != std::string::npos && s.find("/.") != std::string::npos)
    s = std::filesystem::path(s.substr(0, colon)).lexically_normal().string() + s.substr(colon);
  if (!source_dir.empty() && s.compare(0, source_dir.size() + 1, source_dir + "/") == 0)
    s.erase(0, source_dir.size() + 1);
  return s;
}

bool read_hex(const std::string& s, uint64_t* v) {
  if (s.empty() || s.size() > 16 || s.find_first_not_of("0123456789abcdef") != std::string::npos) return false;
  *v = std::strtoull(s.c_str(), nullptr, 16);
  return true;
}

}  // namespace

bool parse_thread_place(const std::string& text, ThreadPlace* out) {
  std::istringstream in(text);
  std::string pc, stack;
  if (!(in >> pc) || pc.rfind("pc=", 0) != 0) return false;
  in >> stack;
  ThreadPlace t;
  t.pc_in_code = pc != "pc=-";
  if (t.pc_in_code && !read_hex(pc.substr(3), &t.pc)) return false;
  if (stack.rfind("stack=", 0) == 0) {
    std::istringstream words(stack.substr(6));
    std::string w;
    while (std::getline(words, w, ',')) {
      uint64_t v;
      if (!read_hex(w, &v)) return false;
      t.stack.push_back(v);
    }
  }
  *out = std::move(t);
  return true;
}

std::string project_function(const std::string& demangled) {
  std::string name = demangled;
  for (size_t at; (at = name.find("(anonymous namespace)")) != std::string::npos;) name.replace(at, 21, "{anon}");
  // Cut the parameter list (the first '(' outside template brackets).
  int depth = 0;
  for (size_t i = 0; i < name.size(); ++i) {
    if (name[i] == '<') ++depth;
    if (name[i] == '>') --depth;
    if (name[i] == '(' && depth == 0) {
      name.erase(i);
      break;
    }
  }
  if (name.rfind("pt::", 0) != 0) return "";
  // The worker's own machinery (its jobs, its fault and stall handling)
  // and the render loop that hands out tiles and waits: never where a
  // part's code is stuck.
  for (const char* mine : {"pt::viewer::{anon}::", "pt::viewer::worker_main", "pt::viewer::StallWatch",
                           "pt::viewer::install_fault_handlers", "pt::viewer::prepare_thread_for_faults",
                           "pt::render_tiles"})
    if (name.rfind(mine, 0) == 0) return "";
  for (const char* ns : {"pt::viewer::", "pt::debug::", "pt::{anon}::", "pt::"})
    if (name.rfind(ns, 0) == 0) return name.substr(std::string(ns).size());
  return name;
}

NamedPlace innermost_function(const std::string& exe, const std::string& source_dir,
                              const std::vector<ThreadPlace>& threads) {
  // Threads running the program's code first, in order; the others only
  // when none is.
  std::vector<const ThreadPlace*> order;
  for (const ThreadPlace& t : threads)
    if (t.pc_in_code) order.push_back(&t);
  for (const ThreadPlace& t : threads)
    if (!t.pc_in_code) order.push_back(&t);
  for (const ThreadPlace* t : order) {
    // The program counter is the instruction itself; a return address is
    // the one after the call, so the call's line is one byte before it.
    std::vector<uint64_t> addresses;
    if (t->pc_in_code) addresses.push_back(t->pc);
    for (uint64_t a : t->stack) addresses.push_back(a - 1);
    std::vector<std::vector<Frame>> frames = addr2line(exe, addresses);
    if (frames.empty())
      for (uint64_t a : addresses) frames.push_back(exported_symbol(a));
    for (const std::vector<Frame>& at : frames)
      for (const Frame& f : at) {
        const std::string name = project_function(f.function);
        if (!name.empty()) return {name, file_line(f.file_line, source_dir)};
      }
  }
  return {};
}

}  // namespace pt::viewer
