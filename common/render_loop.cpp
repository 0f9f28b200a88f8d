#include "common/render_loop.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace pt {

namespace {

using Clock = std::chrono::steady_clock;

void draw_progress(double fraction, double elapsed) {
  const int width = 30;
  const int filled = int(fraction * width);
  char bar[width + 1];
  for (int i = 0; i < width; ++i) bar[i] = i < filled ? '=' : ' ';
  bar[width] = 0;
  const double eta = fraction > 0 ? elapsed * (1 - fraction) / fraction : 0;
  std::fprintf(stderr, "\r[PathTracer] Rendering... [%s] %3d%%  %.0fs left  ", bar,
               int(fraction * 100), eta);
  std::fflush(stderr);
}

}  // namespace

RayStats render_tiles(const PixelRect& rect, const RenderLoopOptions& opts,
                      const std::function<void(int, int)>& pixel) {
  const int ts = std::max(1, opts.tile_size);
  const int tiles_x = std::max(0, (rect.x1 - rect.x0 + ts - 1) / ts);
  const int tiles_y = std::max(0, (rect.y1 - rect.y0 + ts - 1) / ts);
  const int num_tiles = tiles_x * tiles_y;
  const int nthreads = std::max(1, std::min(opts.threads, std::max(1, num_tiles)));

  std::atomic<int> next_tile{0};
  std::atomic<long long> pixels_done{0};
  std::atomic<bool> failed{false};
  std::exception_ptr error;
  std::mutex mu;
  std::condition_variable done_cv;
  int running = nthreads;
  RayStats total;

  auto worker = [&]() {
    RayStats& mine = thread_ray_stats();
    mine = RayStats{};
    try {
      for (int t = next_tile++; t < num_tiles && !failed; t = next_tile++) {
        const int tx = rect.x0 + (t % tiles_x) * ts, ty = rect.y0 + (t / tiles_x) * ts;
        const int ex = std::min(tx + ts, rect.x1), ey = std::min(ty + ts, rect.y1);
        for (int y = ty; y < ey; ++y)
          for (int x = tx; x < ex; ++x) pixel(x, y);
        pixels_done += (long long)(ex - tx) * (ey - ty);
      }
    } catch (...) {
      std::lock_guard<std::mutex> lock(mu);
      if (!error) error = std::current_exception();
      failed = true;
    }
    std::lock_guard<std::mutex> lock(mu);
    total += mine;
    --running;
    done_cv.notify_all();
  };

  std::vector<std::thread> pool;
  pool.reserve(nthreads);
  for (int i = 0; i < nthreads; ++i) pool.emplace_back(worker);

  // The calling thread only watches: it draws the progress bar once the
  // render has taken more than a moment, and only on a terminal.
  const bool tty = opts.progress && isatty(STDERR_FILENO);
  const auto start = Clock::now();
  bool drew = false;
  {
    std::unique_lock<std::mutex> lock(mu);
    while (running > 0) {
      done_cv.wait_for(lock, std::chrono::milliseconds(250));
      const double elapsed = std::chrono::duration<double>(Clock::now() - start).count();
      if (tty && running > 0 && elapsed > 1.0 && rect.area() > 0) {
        draw_progress(double(pixels_done.load()) / double(rect.area()), elapsed);
        drew = true;
      }
    }
  }
  for (auto& th : pool) th.join();
  if (drew) {
    std::fprintf(stderr, "\r%72s\r", "");
    std::fflush(stderr);
  }
  if (error) std::rethrow_exception(error);
  return total;
}

}  // namespace pt
