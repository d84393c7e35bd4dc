// How work runs, as opposed to what it computes: threads, progress and cancellation. Every
// long-running library entry point takes an `Exec`; its results never depend on it.
#pragma once

#include <atomic>
#include <cstdint>
#include <string_view>
#include <utility>

#include <tbb/global_control.h>
#include <tbb/task_arena.h>

namespace iaa {

class Spread;

/// Progress and cancellation: the library reports, the tool draws (app/progress_bar.h), so the
/// library itself never prints.
/// Implementations must be thread-safe: advance() is called from worker threads.
class Progress {
 public:
  virtual ~Progress() = default;
  /// A new phase of `total` units of work starts.
  virtual void start(std::string_view phase, std::uint64_t total) {}
  /// `n` more units are done.
  virtual void advance(std::uint64_t n) {}
  /// The current phase is over.
  virtual void finish() {}
  /// Asks the running computation to stop at its next check.
  void cancel() { cancelled_.store(true, std::memory_order_relaxed); }
  bool cancelled() const { return cancelled_.load(std::memory_order_relaxed); }

 private:
  std::atomic<bool> cancelled_{false};
};

/// Execution settings shared by all parallel algorithms. Results never depend on them.
struct Exec {
  /// Worker threads; 0 means all hardware threads.
  int threads = 0;
  /// Optional progress sink; may be null.
  Progress* progress = nullptr;
  /// Optional: shares the loops with other processes (core/spread.h); may be null.
  Spread* spread = nullptr;

  int resolved_threads() const {
    return threads > 0 ? threads : tbb::this_task_arena::max_concurrency();
  }
  /// Runs f() inside a TBB arena limited to `threads` workers.
  template <class F>
  void run(F&& f) const {
    tbb::task_arena arena(resolved_threads());
    arena.execute(std::forward<F>(f));
  }
};

/// Calls start/finish on an optional Progress.
class ProgressPhase {
 public:
  ProgressPhase(Progress* p, std::string_view phase, std::uint64_t total) : p_(p) {
    if (p_) p_->start(phase, total);
  }
  ~ProgressPhase() {
    if (p_) p_->finish();
  }
  void advance(std::uint64_t n) const {
    if (p_) p_->advance(n);
  }
  bool cancelled() const { return p_ && p_->cancelled(); }

 private:
  Progress* p_;
};

}  // namespace iaa
