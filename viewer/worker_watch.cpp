#include "viewer/worker_watch.h"

#include <dirent.h>
#include <fcntl.h>
#include <link.h>
#include <signal.h>
#include <sys/syscall.h>
#include <ucontext.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace pt::viewer {

namespace {

// ---------------------------------------------------------- the program

// The program's load address and its code, found before any fault.
struct CodeRange {
  uintptr_t lo = 0, hi = 0;
};
uintptr_t g_bias = 0;
CodeRange g_code[8];
int g_code_ranges = 0;

int find_program(dl_phdr_info* info, size_t, void*) {
  // The first object listed is the program itself.
  g_bias = info->dlpi_addr;
  for (int i = 0; i < info->dlpi_phnum && g_code_ranges < 8; ++i) {
    const ElfW(Phdr)& ph = info->dlpi_phdr[i];
    if (ph.p_type == PT_LOAD && (ph.p_flags & PF_X))
      g_code[g_code_ranges++] = {info->dlpi_addr + ph.p_vaddr, info->dlpi_addr + ph.p_vaddr + ph.p_memsz};
  }
  return 1;
}

bool in_code(uintptr_t a) {
  for (int i = 0; i < g_code_ranges; ++i)
    if (a >= g_code[i].lo && a < g_code[i].hi) return true;
  return false;
}

// --------------------------------------------- async-signal-safe helpers

// A pipe: writing one byte from an address succeeds only if the memory
// there can be read (EFAULT otherwise), so the stack scan never faults.
int g_probe[2] = {-1, -1};

bool readable(uintptr_t page) {
  if (::write(g_probe[1], reinterpret_cast<const void*>(page), 1) != 1) return false;
  char c;
  (void)!::read(g_probe[0], &c, 1);
  return true;
}

void registers(void* context, uintptr_t* pc, uintptr_t* sp) {
  const auto* uc = static_cast<const ucontext_t*>(context);
#if defined(__x86_64__)
  *pc = uintptr_t(uc->uc_mcontext.gregs[REG_RIP]);
  *sp = uintptr_t(uc->uc_mcontext.gregs[REG_RSP]);
#elif defined(__aarch64__)
  *pc = uintptr_t(uc->uc_mcontext.pc);
  *sp = uintptr_t(uc->uc_mcontext.sp);
#else
  (void)uc;
  *pc = *sp = 0;
#endif
}

// Words on the stack from `sp` up that are addresses in the program's
// code: the return addresses of the calls in progress (and perhaps a few
// older ones), innermost first.
constexpr int kStackAddresses = 24;
constexpr uintptr_t kScanBytes = 32 << 10;

int scan_stack(uintptr_t sp, uintptr_t* out) {
  int n = 0;
  uintptr_t page_ok = 0;
  for (uintptr_t a = sp & ~uintptr_t(7); sp && a < sp + kScanBytes && n < kStackAddresses; a += 8) {
    const uintptr_t page = a & ~uintptr_t(4095);
    if (page != page_ok) {
      if (!readable(page)) break;
      page_ok = page;
    }
    const uintptr_t w = *reinterpret_cast<const uintptr_t*>(a);
    if (in_code(w)) out[n++] = w;
  }
  return n;
}

char* put(char* p, const char* s) {
  while (*s) *p++ = *s++;
  return p;
}

char* put_hex(char* p, uintptr_t v) {
  char digits[2 * sizeof v];
  int n = 0;
  do {
    digits[n++] = "0123456789abcdef"[v & 15];
    v >>= 4;
  } while (v);
  while (n) *p++ = digits[--n];
  return p;
}

// " pc=<offset or ->stack=<offset>,<offset>,..." (offsets into the file).
char* put_place(char* p, uintptr_t pc, const uintptr_t* stack, int n) {
  p = put(p, "pc=");
  p = in_code(pc) ? put_hex(p, pc - g_bias) : put(p, "-");
  p = put(p, " stack=");
  for (int i = 0; i < n; ++i) {
    if (i) *p++ = ',';
    p = put_hex(p, stack[i] - g_bias);
  }
  return p;
}

const char* signal_name(int sig) {
  switch (sig) {
    case SIGSEGV: return "SIGSEGV";
    case SIGBUS: return "SIGBUS";
    case SIGFPE: return "SIGFPE";
    case SIGILL: return "SIGILL";
    case SIGABRT: return "SIGABRT";
  }
  return "SIGNAL";
}

// ---------------------------------------------------------------- crash

std::atomic<int> g_crashing{0};
char g_report[2048];

void on_fault(int sig, siginfo_t*, void* context) {
  // One report: a second thread faulting meanwhile waits for the end.
  if (g_crashing.exchange(1) != 0)
    for (;;) ::pause();
  uintptr_t pc, sp, stack[kStackAddresses];
  registers(context, &pc, &sp);
  const int n = scan_stack(sp, stack);
  char* p = put(g_report, "CRASH ");
  p = put(p, signal_name(sig));
  *p++ = ' ';
  p = put_place(p, pc, stack, n);
  *p++ = '\n';
  (void)!::write(2, g_report, size_t(p - g_report));
  // Die of the same signal, so that the server sees how the worker ended:
  // the faulting instruction runs again (or abort() raises again) with
  // the default action.
  ::signal(sig, SIG_DFL);
  ::raise(sig);
}

// --------------------------------------------------------------- stall

constexpr int kMaxThreads = 64;
struct Sample {
  std::atomic<int> ready{0};
  uintptr_t pc = 0;
  int n = 0;
  uintptr_t stack[kStackAddresses];
};
Sample g_samples[kMaxThreads];
std::atomic<int> g_next_sample{0};
int g_sample_signal = 0;

void on_sample(int, siginfo_t*, void* context) {
  const int saved = errno;
  const int i = g_next_sample.fetch_add(1);
  if (i < kMaxThreads) {
    Sample& s = g_samples[i];
    uintptr_t sp;
    registers(context, &s.pc, &sp);
    s.n = scan_stack(sp, s.stack);
    s.ready.store(1, std::memory_order_release);
  }
  errno = saved;
}

long this_thread_id() { return ::syscall(SYS_gettid); }

// Samples every other thread and writes one STALL line.
void report_stall(double seconds) {
  std::vector<long> tids;
  if (DIR* d = ::opendir("/proc/self/task")) {
    const long me = this_thread_id();
    while (dirent* e = ::readdir(d)) {
      const long tid = std::atol(e->d_name);
      if (tid > 0 && tid != me) tids.push_back(tid);
    }
    ::closedir(d);
  }
  for (Sample& s : g_samples) s.ready.store(0);
  g_next_sample.store(0);
  int sent = 0;
  for (long tid : tids)
    if (sent < kMaxThreads && ::syscall(SYS_tgkill, ::getpid(), tid, g_sample_signal) == 0) ++sent;
  // Each thread answers at once unless it is descheduled; a second is plenty.
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(1);
  int got = 0;
  while (std::chrono::steady_clock::now() < until) {
    got = 0;
    for (int i = 0; i < sent; ++i) got += g_samples[i].ready.load(std::memory_order_acquire);
    if (got == sent) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  std::string line = "STALL " + std::to_string(int(seconds)) + " ";
  char buf[1024];
  bool first = true;
  for (int i = 0; i < sent; ++i) {
    if (!g_samples[i].ready.load(std::memory_order_acquire)) continue;
    char* p = put_place(buf, g_samples[i].pc, g_samples[i].stack, g_samples[i].n);
    if (!first) line += '|';
    line.append(buf, size_t(p - buf));
    first = false;
  }
  std::fprintf(stderr, "%s\n", line.c_str());
  std::fflush(stderr);
}

}  // namespace

void install_fault_handlers() {
  dl_iterate_phdr(find_program, nullptr);
  if (::pipe2(g_probe, O_CLOEXEC | O_NONBLOCK) != 0) g_probe[0] = g_probe[1] = -1;
  struct sigaction sa = {};
  sa.sa_sigaction = on_fault;
  sa.sa_flags = SA_SIGINFO | SA_ONSTACK;
  sigemptyset(&sa.sa_mask);
  for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) ::sigaction(sig, &sa, nullptr);
  g_sample_signal = SIGRTMIN + 2;
  struct sigaction ss = {};
  ss.sa_sigaction = on_sample;
  ss.sa_flags = SA_SIGINFO | SA_RESTART;
  sigemptyset(&ss.sa_mask);
  ::sigaction(g_sample_signal, &ss, nullptr);
  prepare_thread_for_faults();
}

void prepare_thread_for_faults() {
  // The stack the handler runs on when the thread's own is used up; given
  // back when the thread ends.
  struct AltStack {
    std::vector<char> memory;
    AltStack() : memory(64 << 10) {
      stack_t s = {};
      s.ss_sp = memory.data();
      s.ss_size = memory.size();
      ::sigaltstack(&s, nullptr);
    }
    ~AltStack() {
      stack_t s = {};
      s.ss_flags = SS_DISABLE;
      ::sigaltstack(&s, nullptr);
    }
  };
  thread_local AltStack alt;
  (void)alt;
}

StallWatch::StallWatch(const std::atomic<uint64_t>& progress, double stall_seconds)
    : progress_(progress), stall_seconds_(stall_seconds), thread_([this] { run(); }) {}

StallWatch::~StallWatch() {
  stop_ = true;
  thread_.join();
}

void StallWatch::run() {
  using Clock = std::chrono::steady_clock;
  uint64_t last = progress_.load();
  Clock::time_point since = Clock::now();
  double reported = -1;
  while (!stop_) {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    const uint64_t now = progress_.load();
    if (now != last) {
      last = now;
      since = Clock::now();
      if (reported >= 0) {  // moving again
        std::fprintf(stderr, "STALL 0\n");
        std::fflush(stderr);
      }
      reported = -1;
      continue;
    }
    const double stuck = std::chrono::duration<double>(Clock::now() - since).count();
    // The first report once stuck, then one every few seconds (the
    // function may change, and the page shows how long).
    if (stuck >= stall_seconds_ && (reported < 0 || stuck - reported >= 3.0)) {
      report_stall(stuck);
      reported = stuck;
    }
  }
}

}  // namespace pt::viewer
