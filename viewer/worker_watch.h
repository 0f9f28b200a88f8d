// What a worker says about itself when its code goes wrong: a crash report
// (the signal and where the code was), and a stall report when a job makes
// no progress for a while (where each thread's code is: an endless loop).
//
// Both give code addresses as offsets into this program's file (what
// addr2line reads); the server turns them into function names, and file
// and line where the build has debug information (symbols.h). Lines on
// the worker's standard error:
//   CRASH <signal> pc=<hex> stack=<hex>,<hex>,...
//   STALL <seconds> <pc=<hex> stack=...>|<pc=...>|...     (one group a thread)
//   STALL 0                                                 (moving again)
// The crash handler runs only async-signal-safe code (no allocation, no
// locks, no stdio): it reads the faulting thread's registers, scans its
// stack for addresses inside the program's code, and writes the report in
// one write(); a second thread faulting at the same time waits for the
// process to end instead of writing another.
#pragma once
#include <atomic>
#include <cstdint>
#include <thread>

namespace pt::viewer {

// Installs the crash handlers (SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT)
// and the stall sampler's, and gives the calling thread its own signal
// stack. Call once, first thing in the worker.
void install_fault_handlers();

// Gives the calling thread a signal stack, so that a crash from a stack
// overflow (endless recursion) is reported too. Once per thread (a
// render thread calls it before its first pixel); further calls do
// nothing.
void prepare_thread_for_faults();

// While alive, watches `progress` (a count the job raises as it goes: the
// pixels done): when it has not changed for `stall_seconds`, samples every
// other thread of the process and writes a STALL line, again every few
// seconds while the job stays stuck.
class StallWatch {
 public:
  StallWatch(const std::atomic<uint64_t>& progress, double stall_seconds);
  ~StallWatch();
  StallWatch(const StallWatch&) = delete;
  StallWatch& operator=(const StallWatch&) = delete;

 private:
  void run();
  const std::atomic<uint64_t>& progress_;
  const double stall_seconds_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace pt::viewer
