// The terminal progress bar (progress_bar.h). Application layer: used by tools/ and viz/, never
// by the library modules.
#include "app/progress_bar.h"

#include <unistd.h>

#include <cstdio>

namespace iaa::app {

ProgressBar::ProgressBar(bool quiet) : enabled_(!quiet && ::isatty(STDERR_FILENO) != 0) {}

ProgressBar::~ProgressBar() {
  if (drawn_) std::fputs("\n", stderr);
}

void ProgressBar::start(std::string_view phase, std::uint64_t total) {
  std::lock_guard lock(mu_);
  phase_ = std::string(phase);
  total_ = total;
  done_ = 0;
  start_ = std::chrono::steady_clock::now();
  last_draw_ns_ = 0;
}

void ProgressBar::advance(std::uint64_t n) {
  done_.fetch_add(n, std::memory_order_relaxed);
  if (!enabled_) return;
  // Redraw at most every 100 ms; one thread wins the right to draw.
  const auto now = std::chrono::duration_cast<std::chrono::nanoseconds>(
                       std::chrono::steady_clock::now() - start_)
                       .count();
  auto last = last_draw_ns_.load(std::memory_order_relaxed);
  if (now - last < 100'000'000) return;
  if (!last_draw_ns_.compare_exchange_strong(last, now)) return;
  draw(false);
}

void ProgressBar::finish() {
  if (!enabled_) return;
  draw(true);
  std::lock_guard lock(mu_);
  std::fputs("\n", stderr);
  drawn_ = false;
}

void ProgressBar::draw(bool final) {
  std::lock_guard lock(mu_);
  const std::uint64_t done = final ? total_ : done_.load();
  const double frac = total_ ? static_cast<double>(done) / static_cast<double>(total_) : 1.0;
  const int width = 30;
  const int fill = static_cast<int>(frac * width);
  const double secs =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  std::string bar(static_cast<std::size_t>(fill), '#');
  bar.resize(width, '.');
  std::fprintf(stderr, "\r%-14s [%s] %5.1f%%  %6.1fs", phase_.c_str(), bar.c_str(), 100.0 * frac,
               secs);
  std::fflush(stderr);
  drawn_ = true;
}

}  // namespace iaa::app
